// Sweep members: grids, seeded random and Latin-hypercube samples, and the train/test split.
#include "host/scene/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "host/geometry/random.h"
#include "kernels/core/error.h"

namespace romp::scene {
namespace {

template <class T>
void shuffle(std::vector<T>& items, geometry::Random& random) {
  for (std::size_t i = items.size(); i > 1; --i) std::swap(items[i - 1], items[random.below(i)]);
}

// The members hold a value of every swept parameter: 1,000,000 random members of 40 parameters (a scene of
// 2 KB) took 4 GB and half a minute to list. Checked before they are made.
void check_value_count(std::int64_t members, std::size_t dimensions) {
  constexpr std::int64_t kMostValues = 1000000;
  if (dimensions > 0 && members > kMostValues / std::int64_t(dimensions))
    throw SceneError(fmt::format("[sweep]: {} members of {} parameters would hold {} values; at most {} are allowed",
                                 members, dimensions, members * std::int64_t(dimensions), kMostValues));
}

}  // namespace

SweepSpec read_sweep(TableReader& table, const ParameterValues& declared) {
  SweepSpec sweep;
  const std::string method = table.choice("method", "grid", {"grid", "random", "latin-hypercube"});
  sweep.method = method == "grid"     ? SweepMethod::Grid
                 : method == "random" ? SweepMethod::Random
                                      : SweepMethod::LatinHypercube;
  sweep.samples = table.integer("samples", sweep.method == SweepMethod::Grid ? 0 : 16,
                                sweep.method == SweepMethod::Grid ? Range::closed(0, 0) : Range::closed(1, 1e6));
  sweep.seed = std::uint64_t(table.integer("seed", 0, Range::closed(0, 9e15)));
  sweep.test_fraction = table.number("test_fraction", 0.0, Range::closed_open(0.0, 1.0));
  sweep.train_every = table.integer("train_every", 0, Range::closed(0, 1e6));
  if (sweep.train_every > 0 && sweep.test_fraction > 0.0)
    table.fail("train_every", "cannot be combined with test_fraction (both choose the test members); give one");

  TableReader parameters = table.table("parameters");
  // The grid's values on all axes: `count` makes 100,000 of them from a few bytes, so an 8 MB scene of such
  // axes would ask for 120 GB before sweep_members bounds the members they make.
  constexpr std::size_t kMostGridValues = 1000000;
  std::size_t grid_values = 0;
  for (const std::string& name : parameters.keys()) {
    if (!declared.count(name)) {
      std::string known;
      for (const auto& [parameter, value] : declared) known += (known.empty() ? "" : ", ") + parameter;
      parameters.fail(name, fmt::format("sweeps an undeclared parameter; declare it in [parameters] (declared: {})",
                                        known.empty() ? "none" : known));
    }
    TableReader axis_table = parameters.table(name);
    SweepAxis axis;
    axis.parameter = name;
    if (sweep.method == SweepMethod::Grid && axis_table.has("values")) {
      axis.values = axis_table.numbers("values", {}, Range::any(), 1, 100000);
    } else {
      const std::vector<double> range = axis_table.required_numbers("range", Range::any(), 2, 2);
      if (!(range[0] < range[1])) axis_table.fail("range", "needs low < high");
      axis.low = range[0];
      axis.high = range[1];
      if (sweep.method == SweepMethod::Grid) {
        const std::int64_t count = axis_table.integer("count", 2, Range::closed(1, 100000));
        for (std::int64_t i = 0; i < count; ++i)
          axis.values.push_back(count == 1 ? 0.5 * (axis.low + axis.high)
                                           : axis.low + (axis.high - axis.low) * double(i) / double(count - 1));
      }
    }
    grid_values += axis.values.size();
    if (grid_values > kMostGridValues)
      axis_table.fail("", fmt::format("the grid's axes take more than {} values in all", kMostGridValues));
    axis_table.finish();
    sweep.axes.push_back(std::move(axis));
  }
  if (sweep.axes.empty()) parameters.fail("", "a sweep needs at least one parameter, e.g. [sweep.parameters.gravity]");
  parameters.finish();
  return sweep;
}

std::vector<SweepMember> sweep_members(const SweepSpec& sweep) {
  std::vector<SweepMember> members;
  geometry::Random random(sweep.seed);
  const std::size_t dimensions = sweep.axes.size();
  if (sweep.method == SweepMethod::Grid) {
    // Multiplied with the bound checked first: 4 axes of 65,536 values once wrapped to 0 members.
    constexpr std::int64_t kMostMembers = 1000000;
    std::int64_t count = 1;
    for (const SweepAxis& axis : sweep.axes) {
      const std::int64_t values = std::int64_t(axis.values.size());
      if (values > kMostMembers / count)
        throw SceneError(fmt::format("[sweep]: the grid of {} axes has more than {} members; at most {} are allowed",
                                     sweep.axes.size(), kMostMembers, kMostMembers));
      count *= values;
    }
    check_value_count(count, dimensions);
    for (std::int64_t m = 0; m < count; ++m) {
      SweepMember member;
      member.index = m;
      std::int64_t rest = m;
      for (std::size_t d = dimensions; d-- > 0;) {
        const SweepAxis& axis = sweep.axes[d];
        const std::int64_t n = std::int64_t(axis.values.size());
        member.values[axis.parameter] = axis.values[std::size_t(rest % n)];
        rest /= n;
      }
      members.push_back(std::move(member));
    }
  } else {
    const std::int64_t count = sweep.samples;
    check_value_count(count, dimensions);
    // Latin hypercube: each axis is cut into `count` strata, one sample per stratum, strata paired
    // across axes by an independent random permutation per axis.
    std::vector<std::vector<std::int64_t>> strata(dimensions);
    for (std::size_t d = 0; d < dimensions; ++d) {
      strata[d].resize(std::size_t(count));
      std::iota(strata[d].begin(), strata[d].end(), 0);
      if (sweep.method == SweepMethod::LatinHypercube) shuffle(strata[d], random);
    }
    for (std::int64_t m = 0; m < count; ++m) {
      SweepMember member;
      member.index = m;
      for (std::size_t d = 0; d < dimensions; ++d) {
        const SweepAxis& axis = sweep.axes[d];
        const double u = sweep.method == SweepMethod::Random
                             ? random.uniform()
                             : (double(strata[d][std::size_t(m)]) + random.uniform()) / double(count);
        member.values[axis.parameter] = axis.low + (axis.high - axis.low) * u;
      }
      members.push_back(std::move(member));
    }
  }
  if (sweep.train_every > 0) {
    // Evenly spaced split (the ROM paper's Sec. 5.3 trains on every third poke azimuth), so training
    // covers the parameter range without the gaps a random draw can leave.
    for (SweepMember& member : members) member.test = member.index % sweep.train_every != 0;
    return members;
  }
  // Seeded split: a random subset of round(test_fraction × N) members is held out.
  std::vector<std::size_t> order(members.size());
  std::iota(order.begin(), order.end(), 0);
  geometry::Random split_random(sweep.seed ^ 0x5EEDu);
  shuffle(order, split_random);
  const auto tests = std::size_t(std::llround(sweep.test_fraction * double(members.size())));
  for (std::size_t i = 0; i < tests; ++i) members[order[i]].test = true;
  return members;
}

}  // namespace romp::scene
