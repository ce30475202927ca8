// Sweep members: grids in a fixed order, seeded random and Latin-hypercube samples, and the split.
#include "host/scene/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "host/scene/toml_reader.h"

namespace romp::scene {
namespace {

SweepSpec two_axis_sweep(SweepMethod method) {
  SweepSpec sweep;
  sweep.method = method;
  sweep.samples = 20;
  sweep.seed = 7;
  sweep.test_fraction = 0.25;
  sweep.axes = {{"gravity", {5.0, 10.0, 15.0}, 5.0, 15.0}, {"angle", {0.0, 90.0}, 0.0, 90.0}};
  return sweep;
}

TEST(Sweep, GridIsTheFullFactorialWithTheLastAxisFastest) {
  const std::vector<SweepMember> members = sweep_members(two_axis_sweep(SweepMethod::Grid));
  ASSERT_EQ(members.size(), 6u);
  EXPECT_EQ(members[0].values.at("gravity"), 5.0);
  EXPECT_EQ(members[0].values.at("angle"), 0.0);
  EXPECT_EQ(members[1].values.at("angle"), 90.0);
  EXPECT_EQ(members[5].values.at("gravity"), 15.0);
  std::set<std::pair<double, double>> distinct;
  for (const SweepMember& m : members) distinct.insert({m.values.at("gravity"), m.values.at("angle")});
  EXPECT_EQ(distinct.size(), 6u);
}

// 65,536⁴ members once wrapped to 0 (and the sweep exited 0 having run nothing).
TEST(Sweep, AGridBeyondAMillionMembersIsRefusedNotWrapped) {
  SweepSpec sweep = two_axis_sweep(SweepMethod::Grid);
  sweep.axes.clear();
  for (const char* name : {"a", "b", "c", "d"}) sweep.axes.push_back({name, std::vector<double>(65536, 1.0), 0.0, 1.0});
  try {
    sweep_members(sweep);
    FAIL() << "accepted";
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("more than 1000000 members"), std::string::npos) << error.what();
  }
  sweep.axes.resize(1);
  EXPECT_EQ(sweep_members(sweep).size(), 65536u);
}

// 1,000,000 random members of 40 parameters (tests/fuzz/corpus/scene/regression_oom_sweep_values.toml) took
// 4 GB to list: the values the members hold are bounded, for every method, before any member is made.
TEST(Sweep, MembersHoldingBeyondAMillionValuesAreRefused) {
  for (const SweepMethod method : {SweepMethod::Random, SweepMethod::LatinHypercube, SweepMethod::Grid}) {
    SweepSpec sweep = two_axis_sweep(method);
    sweep.samples = 1000000;
    if (method == SweepMethod::Grid)
      sweep.axes = {{"a", std::vector<double>(1000, 1.0), 0.0, 1.0},
                    {"b", std::vector<double>(1000, 1.0), 0.0, 1.0},
                    {"c", {1.0}, 0.0, 1.0}};
    try {
      sweep_members(sweep);
      FAIL() << "accepted";
    } catch (const SceneError& error) {
      EXPECT_NE(std::string(error.what()).find("values; at most 1000000 are allowed"), std::string::npos)
          << error.what();
    }
  }
  SweepSpec sweep = two_axis_sweep(SweepMethod::Random);
  sweep.samples = 500000;
  EXPECT_EQ(sweep_members(sweep).size(), 500000u);
}

TEST(Sweep, LatinHypercubePutsOneSampleInEveryStratumOfEveryAxis) {
  const SweepSpec sweep = two_axis_sweep(SweepMethod::LatinHypercube);
  const std::vector<SweepMember> members = sweep_members(sweep);
  ASSERT_EQ(members.size(), 20u);
  for (const SweepAxis& axis : sweep.axes) {
    std::set<int> strata;
    for (const SweepMember& m : members) {
      const double u = (m.values.at(axis.parameter) - axis.low) / (axis.high - axis.low);
      ASSERT_GE(u, 0.0);
      ASSERT_LT(u, 1.0);
      strata.insert(int(u * 20.0));
    }
    EXPECT_EQ(strata.size(), 20u) << axis.parameter;
  }
}

TEST(Sweep, SeedFixesMembersAndSplit) {
  for (SweepMethod method : {SweepMethod::Random, SweepMethod::LatinHypercube}) {
    SweepSpec sweep = two_axis_sweep(method);
    const std::vector<SweepMember> a = sweep_members(sweep), b = sweep_members(sweep);
    sweep.seed = 8;
    const std::vector<SweepMember> c = sweep_members(sweep);
    int tests = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].values, b[i].values);
      EXPECT_EQ(a[i].test, b[i].test);
      tests += a[i].test;
    }
    EXPECT_EQ(tests, 5);  // round(0.25 × 20)
    EXPECT_NE(a[0].values, c[0].values);
  }
}

TEST(Sweep, TrainEveryHoldsOutAllButEveryNthMember) {
  SweepSpec sweep = two_axis_sweep(SweepMethod::Grid);
  sweep.test_fraction = 0.0;
  sweep.train_every = 3;
  const std::vector<SweepMember> members = sweep_members(sweep);
  ASSERT_EQ(members.size(), 6u);
  for (const SweepMember& m : members) EXPECT_EQ(m.test, m.index % 3 != 0) << m.index;
}

}  // namespace
}  // namespace romp::scene
