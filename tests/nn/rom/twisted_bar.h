// An analytic deformation family for ROM tests, written as a sweep folder: a bar [0, 1] × [0, 0.2] × [0, 0.2]
// twisted about its long axis, the cross-section at X₀ turned by θ(t)·X₀ with θ(t) = θ_max sin(πt / 2T), one
// member per θ_max. Positions, deformation gradients and velocities are exact.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "nn/io/snapshot_writer.h"

namespace romp::test {

struct TwistedBar {
  int members = 8;         // θ_max evenly in [min_twist, max_twist]
  double min_twist = 0.2;  // rad
  double max_twist = 1.0;
  std::vector<int> test_members = {2, 5};  // held out (interior values: interpolation)
  int frames = 11;                         // t = 0 .. end_time
  double end_time = 0.5;                   // s
  int nx = 20, ny = 5, nz = 5;             // lattice of material points (cell centres)

  double twist(int member) const { return min_twist + (max_twist - min_twist) * member / (members - 1); }

  // Writes DIR/manifest.json and DIR/member_NNNNNN.h5 as `romp sweep` would.
  void write(const std::filesystem::path& dir) const {
    std::filesystem::create_directories(dir);
    const std::vector<std::array<double, 3>> reference = reference_positions();
    io::SnapshotHeader header;
    const std::size_t n = reference.size();
    header.X.resize(3 * n);
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) header.X[c * n + p] = float(reference[p][c]);
    header.mass.assign(n, 1.0f);
    header.volume0.assign(n, 1.0f);
    header.material.assign(n, 0);
    header.scene = "twisted bar";
    header.parameter_names = {"twist"};
    std::string entries;
    for (int m = 0; m < members; ++m) {
      const std::string name = "member_" + std::string(6 - std::to_string(m).size(), '0') + std::to_string(m) + ".h5";
      header.parameter_values = {twist(m)};
      io::SnapshotWriter writer((dir / name).string(), header, io::kFieldX | io::kFieldV | io::kFieldF);
      for (int f = 0; f < frames; ++f) writer.append_frame(frame(reference, twist(m), end_time * f / (frames - 1), f));
      writer.finish();
      const bool test = std::find(test_members.begin(), test_members.end(), m) != test_members.end();
      entries += std::string(m ? ",\n" : "") + "{\"index\": " + std::to_string(m) +
                 ", \"values\": {\"twist\": " + std::to_string(twist(m)) + "}, \"split\": \"" +
                 (test ? "test" : "train") + "\", \"snapshot\": \"" + name + "\"}";
    }
    std::ofstream(dir / "manifest.json") << "{\"format\": \"romp-sweep\", \"format_version\": 1, "
                                         << "\"parameters\": [\"twist\"], \"members\": [\n"
                                         << entries << "]}\n";
  }

  std::vector<std::array<double, 3>> reference_positions() const {
    std::vector<std::array<double, 3>> reference;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < nz; ++k) reference.push_back({(i + 0.5) / nx, 0.2 * (j + 0.5) / ny, 0.2 * (k + 0.5) / nz});
    return reference;
  }

 private:
  io::FrameData frame(const std::vector<std::array<double, 3>>& reference, double twist_max, double t,
                      int index) const {
    const double pi = std::acos(-1.0);
    const double theta = twist_max * std::sin(pi * t / (2 * end_time));
    const double theta_rate = twist_max * pi / (2 * end_time) * std::cos(pi * t / (2 * end_time));
    const std::size_t n = reference.size();
    io::FrameData data;
    data.time = t;
    data.step = index;
    data.x.resize(3 * n);
    data.v.resize(3 * n);
    data.F.resize(9 * n);
    for (std::size_t p = 0; p < n; ++p) {
      const double X0 = reference[p][0], d1 = reference[p][1] - 0.1, d2 = reference[p][2] - 0.1;
      const double angle = theta * X0, c = std::cos(angle), s = std::sin(angle);
      // Rotated offset R(α)d and its derivative R'(α)d.
      const double r1 = c * d1 - s * d2, r2 = s * d1 + c * d2;
      const double t1 = -s * d1 - c * d2, t2 = c * d1 - s * d2;
      const double x[3] = {X0, 0.1 + r1, 0.1 + r2};
      const double v[3] = {0.0, theta_rate * X0 * t1, theta_rate * X0 * t2};
      const double F[9] = {1, 0, 0, theta * t1, c, -s, theta * t2, s, c};
      for (int i = 0; i < 3; ++i) {
        data.x[i * n + p] = float(x[i]);
        data.v[i * n + p] = float(v[i]);
      }
      for (int e = 0; e < 9; ++e) data.F[e * n + p] = float(F[e]);
    }
    return data;
  }
};

}  // namespace romp::test
