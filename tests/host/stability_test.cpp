// The fast corner of the stability matrix (romp-bench's stability suite runs the whole, results in
// bench/results/stability.md): a soft cube through every extreme scenario, plain and enriched, and
// a stiff one with plain particles; each must finish finite with bounded energy. Runs on the
// backend the binary was started with.
#include <gtest/gtest.h>

#include <tuple>

#include "host/stability_case.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

using Params = std::tuple<StabilityScenario, bool, double>;

class StabilityCases : public ::testing::TestWithParam<Params> {};

TEST_P(StabilityCases, FinishFiniteWithBoundedEnergy) {
  StabilityCase c;
  std::tie(c.scenario, c.enriched, c.youngs_modulus) = GetParam();
  c.poissons_ratio = 0.3;
  const StabilityOutcome outcome = run_stability_case(test::exec(), c, StabilityBudget{});
  EXPECT_EQ(outcome.status, StabilityOutcome::Status::Finished) << c.name() << ": " << outcome.message;
  EXPECT_TRUE(outcome.acceptable()) << c.name() << ": energy ratio " << outcome.energy_ratio;
}

const auto kScenarios = ::testing::Values(StabilityScenario::FreeFallBounce, StabilityScenario::CompressRelease,
                                          StabilityScenario::ForcedInversion, StabilityScenario::Spin,
                                          StabilityScenario::WallImpact);
INSTANTIATE_TEST_SUITE_P(Soft, StabilityCases, ::testing::Combine(kScenarios, ::testing::Bool(), ::testing::Values(1e4)));
INSTANTIATE_TEST_SUITE_P(Stiff, StabilityCases, ::testing::Combine(kScenarios, ::testing::Values(false), ::testing::Values(1e6)));

}  // namespace
}  // namespace romp
