// Shared by the I/O tests: a fresh folder per test, random snapshot contents and file helpers.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/snapshot_layout.h"
#include "tests/support/scratch_folder.h"

namespace romp::io::testing {

// A folder of its own for each test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  std::string file(const std::string& name) const { return folder_.file(name); }
  std::vector<std::string> folder_contents() const { return folder_.contents(); }

  romp::test::ScratchFolder folder_;
};

using romp::test::error_message;

inline std::vector<float> random_floats(std::size_t count, std::mt19937& random) {
  std::normal_distribution<float> normal(0.0f, 10.0f);
  std::vector<float> values(count);
  for (float& value : values) value = normal(random);
  return values;
}

// A header for n particles with random arrays and a two-parameter μ.
inline SnapshotHeader random_header(std::int64_t n, std::mt19937& random) {
  SnapshotHeader header;
  header.X = random_floats(std::size_t(3 * n), random);
  header.mass = random_floats(std::size_t(n), random);
  header.volume0 = random_floats(std::size_t(n), random);
  std::uniform_int_distribution<std::int32_t> material(0, 4);
  header.material.resize(std::size_t(n));
  for (std::int32_t& id : header.material) id = material(random);
  header.group.resize(std::size_t(n));
  for (std::int32_t& group : header.group) group = material(random) - 1;  // −1: none
  header.scene = "[scene]\nname = \"test\"\n# résolu\n";
  header.parameter_names = {"E", "nu"};
  header.parameter_values = {1e5, 0.3};
  header.romp_version = "0.1.0";
  header.commit = "abc1234-dirty";
  return header;
}

// A frame with random values in every field (also the ones a writer may not select).
inline FrameData random_frame(std::int64_t n, double time, std::int64_t step, std::mt19937& random) {
  FrameData frame;
  frame.time = time;
  frame.step = step;
  // Every field a snapshot can hold, and the totals.
  for (const FieldInfo& info : kFieldInfos)
    frame.field(info.bit) = random_floats(std::size_t(info.components * n), random);
  FrameTotals totals;
  totals.kinetic_energy = random_floats(1, random)[0];
  totals.elastic_energy = 1.0 / 3.0;
  totals.gravitational_energy = -random_floats(1, random)[0];
  totals.linear_momentum = {1.0, -2.0, 1e-300};
  totals.angular_momentum = {0.0, -0.0, 7.0};
  frame.totals = totals;
  return frame;
}

inline bool bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace romp::io::testing
