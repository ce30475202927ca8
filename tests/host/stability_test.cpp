// The fast corner of the stability matrix (romp-bench's stability suite runs the whole, results in
// bench/results/stability.md): a soft cube through every extreme scenario, plain and enriched, a
// stiff one with plain particles, and the stiff one enriched with the implicit step (enriched
// corners are unknowns of the solve); each must finish finite with bounded energy. Runs on the
// backend the binary was started with.
#include <gtest/gtest.h>

#include <tuple>

#include "host/analysis/stability_case.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

using Params = std::tuple<analysis::StabilityScenario, bool, double>;

class StabilityCases : public ::testing::TestWithParam<Params> {};

TEST_P(StabilityCases, FinishFiniteWithBoundedEnergy) {
  analysis::StabilityCase c;
  std::tie(c.scenario, c.enriched, c.youngs_modulus) = GetParam();
  c.poissons_ratio = 0.3;
  const analysis::StabilityOutcome outcome = analysis::run_stability_case(test::exec(), c, analysis::StabilityBudget{});
  EXPECT_EQ(outcome.status, analysis::StabilityOutcome::Status::Finished) << c.name() << ": " << outcome.message;
  EXPECT_TRUE(outcome.acceptable()) << c.name() << ": energy ratio " << outcome.energy_ratio;
}

const auto kScenarios =
    ::testing::Values(analysis::StabilityScenario::FreeFallBounce, analysis::StabilityScenario::CompressRelease,
                      analysis::StabilityScenario::ForcedInversion, analysis::StabilityScenario::Spin,
                      analysis::StabilityScenario::WallImpact);
INSTANTIATE_TEST_SUITE_P(Soft, StabilityCases,
                         ::testing::Combine(kScenarios, ::testing::Bool(), ::testing::Values(1e4)));
INSTANTIATE_TEST_SUITE_P(Stiff, StabilityCases,
                         ::testing::Combine(kScenarios, ::testing::Values(false), ::testing::Values(1e6)));

// The stiff cube, enriched, with the implicit step at 8 times the explicit cfl, through the scenarios
// that enrich (measured: the largest share of enriched particles in one substep is 0.18 compressed,
// 0.52 inverted and 0.75 at the wall): enriched corners are unknowns of the solve.
class ImplicitEnrichedCases : public ::testing::TestWithParam<analysis::StabilityScenario> {};

TEST_P(ImplicitEnrichedCases, FinishFiniteWithBoundedEnergyWhileEnriched) {
  analysis::StabilityCase c;
  c.scenario = GetParam();
  c.youngs_modulus = 1e6;
  c.enriched = true;
  c.implicit = true;
  const analysis::StabilityOutcome outcome = analysis::run_stability_case(test::exec(), c, analysis::StabilityBudget{});
  EXPECT_EQ(outcome.status, analysis::StabilityOutcome::Status::Finished) << c.name() << ": " << outcome.message;
  EXPECT_TRUE(outcome.acceptable()) << c.name() << ": energy ratio " << outcome.energy_ratio;
  EXPECT_GT(outcome.largest_enriched_share, 0.1) << c.name() << ": the case no longer enriches";
}

INSTANTIATE_TEST_SUITE_P(Stiff, ImplicitEnrichedCases,
                         ::testing::Values(analysis::StabilityScenario::CompressRelease,
                                           analysis::StabilityScenario::ForcedInversion,
                                           analysis::StabilityScenario::WallImpact));

}  // namespace
}  // namespace romp
