// stability suite: the robust-elasticity matrix (the enriched-MPM issue's item 7). Every hyperelastic
// model × E × ν × scenario × {explicit, implicit} × {plain, enriched} runs a small cube under a
// budget; each case is recorded as acceptable or not (ends finite with bounded energy, or stops with
// a message), with its status, the simulated share of its duration and its energy ratio.
//
// --set min_youngs=X and --set max_youngs=X limit E to [X_min, X_max]; --set implicit=0|1 and
// --set enriched=0|1 keep one integrator or one particle variant; --set substeps=N and
// --set seconds=S set each case's budget (default 20000 substeps, 20 s).
#include <fmt/format.h>

#include <algorithm>

#include "bench/suites/suites.h"
#include "host/analysis/stability_case.h"
#include "kernels/core/error.h"

namespace romp::bench {
namespace {

double parameter(const Options& options, const char* name, double fallback) {
  const auto found = options.parameters.find(name);
  return found == options.parameters.end() ? fallback : found->second;
}

// Whether --set NAME=0|1 (absent: both) keeps the variant whose NAME is `value`.
bool wanted(const Options& options, const char* name, bool value) {
  const auto found = options.parameters.find(name);
  if (found == options.parameters.end()) return true;
  ROMP_CHECK(found->second == 0.0 || found->second == 1.0,
             fmt::format("stability suite: --set {}={} must be 0 or 1", name, found->second));
  return (found->second == 1.0) == value;
}

}  // namespace

void run_stability_suite(Context& context) {
  const Options& options = context.options();
  analysis::StabilityBudget budget;
  budget.max_substeps = std::int64_t(parameter(options, "substeps", 20000));
  budget.max_wall_seconds = parameter(options, "seconds", 20.0);
  const double min_youngs = parameter(options, "min_youngs", 0.0);
  const double max_youngs = parameter(options, "max_youngs", 1e9);
  const Exec exec = context.execs().back();  // the GPU when asked for, else the CPU at its most threads

  int cases = 0, acceptable = 0, finished = 0;
  for (const material::MaterialModel model : {material::MaterialModel::FixedCorotated,
                                              material::MaterialModel::NeoHookean, material::MaterialModel::HenckyStVK})
    for (const double youngs : {1e4, 1e6, 1e8, 1e9}) {
      if (youngs < min_youngs || youngs > max_youngs) continue;
      for (const double poisson : {0.0, 0.3, 0.45, 0.49})
        for (const analysis::StabilityScenario scenario :
             {analysis::StabilityScenario::FreeFallBounce, analysis::StabilityScenario::CompressRelease,
              analysis::StabilityScenario::ForcedInversion, analysis::StabilityScenario::Spin,
              analysis::StabilityScenario::WallImpact})
          for (const bool implicit : {false, true})
            for (const bool enriched : {false, true}) {
              if (!wanted(options, "implicit", implicit) || !wanted(options, "enriched", enriched)) continue;
              const analysis::StabilityCase c{model, youngs, poisson, scenario, enriched, implicit};
              const analysis::StabilityOutcome outcome = analysis::run_stability_case(exec, c, budget);
              ++cases;
              acceptable += outcome.acceptable();
              finished += outcome.status == analysis::StabilityOutcome::Status::Finished && outcome.acceptable();
              const std::string key = "stability." + c.name();
              context.record(key + ".acceptable", outcome.acceptable() ? 1.0 : 0.0);
              context.record(key + ".simulated_fraction", outcome.simulated_seconds / outcome.end_seconds);
              context.record(key + ".energy_ratio", outcome.energy_ratio);
              context.record(key + ".largest_enriched_share", outcome.largest_enriched_share);
              fmt::print(
                  "{:<72} {:<15} t {:.4f}/{:.4f} s  {:>6} substeps  energy x{:<9.3g} enriched {:4.2f} "
                  "{:6.2f} s  {}{}\n",
                  c.name(), outcome.status_name(), outcome.simulated_seconds, outcome.end_seconds, outcome.substeps,
                  outcome.energy_ratio, outcome.largest_enriched_share, outcome.wall_seconds,
                  outcome.acceptable() ? "ok" : "NOT OK",
                  outcome.message.empty() ? "" : "  " + outcome.message.substr(0, 160));
            }
    }
  context.record("stability.cases", cases);
  context.record("stability.acceptable", acceptable);
  context.record("stability.finished_within_bounds", finished);
}

}  // namespace romp::bench
