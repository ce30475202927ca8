// Bridson's Poisson-disk sampling in 3-D with a background grid of one point per cell.
#include "host/geometry/poisson_disk.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <utility>

#include <fmt/format.h>

#include "host/geometry/random.h"
#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

// Background cells at most this many, so a radius far below the region's size fails clearly
// instead of exhausting memory (4 bytes each).
constexpr double kMaxCells = 2e9;

}  // namespace

std::vector<Vec3<double>> poisson_disk_sample(const Bounds& region, double radius, std::uint64_t seed, int candidates) {
  ROMP_CHECK(radius > 0.0 && std::isfinite(radius), "the Poisson-disk radius must be finite and > 0");
  ROMP_CHECK(candidates >= 1, "Bridson's algorithm needs at least one candidate per active point");
  // A cell's diagonal is the radius, so a cell holds at most one point, and the points closer than
  // the radius to a candidate lie in the 5×5×5 block of cells around its own, less the 8 corners
  // (a whole cell away along every axis, so at least the radius away). The grid is padded by two
  // empty cells on every side so that block never needs clamping.
  constexpr std::ptrdiff_t kPad = 2;
  const double cell = radius / std::sqrt(3.0);
  const Vec3<double> size = region.size();
  std::ptrdiff_t cells[3], padded[3];
  double total_cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double n = std::max(1.0, std::ceil(size[a] / cell));
    total_cells *= n + 2.0 * kPad;
    if (total_cells > kMaxCells)
      throw Error(
          fmt::format("Poisson-disk sampling of a region of size {} x {} x {} at radius {} needs more than {:g} "
                      "background cells; raise the sampling spacing",
                      size[0], size[1], size[2], radius, kMaxCells));
    cells[a] = std::ptrdiff_t(n);
    padded[a] = cells[a] + 2 * kPad;
  }
  std::vector<std::int32_t> grid(std::size_t(total_cells), -1);
  const auto slot_of = [&](const Vec3<double>& p) {
    std::ptrdiff_t index[3];
    for (int a = 0; a < 3; ++a)
      index[a] =
          kPad + std::clamp(std::ptrdiff_t(std::floor((p[a] - region.low[a]) / cell)), std::ptrdiff_t(0), cells[a] - 1);
    return (index[2] * padded[1] + index[1]) * padded[0] + index[0];
  };
  // The block's cells as offsets in the grid, nearest first: a candidate is mostly refused for a
  // point in a cell next to its own, and then the search stops early.
  std::vector<std::pair<int, std::ptrdiff_t>> block;
  for (int k = -2; k <= 2; ++k)
    for (int j = -2; j <= 2; ++j)
      for (int i = -2; i <= 2; ++i)
        if (std::abs(i) + std::abs(j) + std::abs(k) < 6)
          block.emplace_back(i * i + j * j + k * k, (std::ptrdiff_t(k) * padded[1] + j) * padded[0] + i);
  std::stable_sort(block.begin(), block.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::ptrdiff_t> neighbours;
  for (const auto& entry : block) neighbours.push_back(entry.second);

  std::vector<Vec3<double>> points;
  std::vector<std::int32_t> active;
  Random random(seed);
  const auto insert = [&](const Vec3<double>& p) {
    grid[std::size_t(slot_of(p))] = std::int32_t(points.size());
    active.push_back(std::int32_t(points.size()));
    points.push_back(p);
  };
  // Whether q is closer than the radius to a point, or its cell is taken (possible only at exactly
  // the radius, and refused so the one-point-per-cell invariant holds).
  const auto blocked = [&](const Vec3<double>& q) {
    const std::ptrdiff_t own = slot_of(q);
    if (grid[std::size_t(own)] >= 0) return true;
    for (std::ptrdiff_t offset : neighbours) {
      const std::int32_t other = grid[std::size_t(own + offset)];
      if (other >= 0 && squared_norm(points[std::size_t(other)] - q) < radius * radius) return true;
    }
    return false;
  };

  insert(Vec3<double>(random.uniform(region.low[0], region.high[0]), random.uniform(region.low[1], region.high[1]),
                      random.uniform(region.low[2], region.high[2])));
  while (!active.empty()) {
    const std::size_t chosen = std::size_t(random.below(active.size()));
    const Vec3<double> center = points[active[chosen]];
    bool emitted = false;
    for (int attempt = 0; attempt < candidates && !emitted; ++attempt) {
      // Uniform in the shell radius ≤ |d| ≤ 2 radius, by rejection from the enclosing cube (46% are
      // kept): no trigonometry, whose last bits differ between math libraries.
      Vec3<double> d;
      double d2;
      do {
        d = Vec3<double>(random.uniform(-2.0, 2.0), random.uniform(-2.0, 2.0), random.uniform(-2.0, 2.0));
        d2 = squared_norm(d);
      } while (d2 < 1.0 || d2 > 4.0);
      const Vec3<double> q = center + radius * d;
      if (region.contains(q) && !blocked(q)) {
        insert(q);
        emitted = true;
      }
    }
    if (!emitted) {
      active[chosen] = active.back();
      active.pop_back();
    }
  }
  return points;
}

}  // namespace romp::geometry
