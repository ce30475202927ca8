// Stability cases: scene construction per scenario, the budgeted run, and the energy record.
#include "host/analysis/stability_case.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "host/analysis/mechanical_energy.h"
#include "host/engine/full_order_sim.h"
#include "host/geometry/lattice_domains.h"
#include "host/geometry/sampling.h"
#include "kernels/material/lame.h"

namespace romp::analysis {
namespace {

constexpr float kDx = 0.01f;  // a 20-cell domain of 0.2 m
constexpr std::int32_t kCells = 20;
constexpr float kSide = 0.04f;  // the cube, 8 particles per side at 2 per cell
constexpr float kDensity = 1000.0f;
constexpr float kMinStretch = 0.1f;
constexpr float kFloor = 3 * kDx;  // the wall nodes end here
// Heights for the gravitational energy are measured from the floor.
const Vec3<float> kFloorOrigin(0.0f, kFloor, 0.0f);

const char* scenario_name(StabilityScenario scenario) {
  switch (scenario) {
    case StabilityScenario::FreeFallBounce: return "free-fall-bounce";
    case StabilityScenario::CompressRelease: return "compress-release";
    case StabilityScenario::ForcedInversion: return "forced-inversion";
    case StabilityScenario::Spin: return "spin";
    case StabilityScenario::WallImpact: return "wall-impact";
  }
  return "?";
}

const char* model_name(material::MaterialModel model) {
  switch (model) {
    case material::MaterialModel::FixedCorotated: return "fixed-corotated";
    case material::MaterialModel::NeoHookean: return "neo-hookean";
    case material::MaterialModel::HenckyStVK: return "hencky-stvk";
    default: return "other";
  }
}

material::MaterialParams<float> elastic_params(const StabilityCase& c) {
  using Params = material::MaterialParams<float>;
  const material::Lame<float> lame =
      material::lame_from_young_poisson(float(c.youngs_modulus), float(c.poissons_ratio));
  switch (c.model) {
    case material::MaterialModel::NeoHookean: return Params::neo_hookean(lame).with_min_stretch(kMinStretch);
    case material::MaterialModel::HenckyStVK: return Params::hencky_stvk(lame).with_min_stretch(kMinStretch);
    default: return Params::fixed_corotated(lame).with_min_stretch(kMinStretch);
  }
}

struct Setup {
  engine::FullOrderConfig config;
  mpm::ParticleInit init;
  double end = 0.0;
  double reference_time = 0.0;  // energies after this instant are compared with the energy at it
};

Setup build(const StabilityCase& c) {
  Setup s;
  engine::FullOrderConfig& config = s.config;
  config.dx = kDx;
  config.domain_cells = {kCells, kCells, kCells};
  config.gravity = Vec3<float>::zero();
  config.materials = {engine::MaterialSpec{elastic_params(c), kDensity}};
  config.enrichment_threshold = c.enriched ? 0.6f : 0.0f;
  if (c.implicit) {
    config.integrator = engine::Integrator::Implicit;
    config.cfl = kImplicitStabilityCfl;
  }
  config.transfer = mpm::Transfer::PicFlip;  // the enriched-MPM paper's transfer, for both variants

  const float centre = 0.5f * float(kCells) * kDx;
  Vec3<float> low = Vec3<float>::constant(centre - 0.5f * kSide), high = Vec3<float>::constant(centre + 0.5f * kSide);
  if (c.scenario == StabilityScenario::CompressRelease || c.scenario == StabilityScenario::FreeFallBounce) {
    // On (or, falling, above) the floor.
    const float bottom = c.scenario == StabilityScenario::FreeFallBounce ? kFloor + 0.06f : kFloor + 0.5f * kDx;
    low[1] = bottom;
    high[1] = bottom + kSide;
  }
  const geometry::SamplingSpec lattice{geometry::SamplingMethod::Lattice, 2, kDx};
  s.init = c.enriched ? geometry::sample_box_with_domains(low, high, lattice, kDensity)
                      : geometry::sample_box(low, high, lattice, kDensity);
  mpm::ParticleInit& init = s.init;
  const Index n = init.count();
  auto set_velocity = [&](Index p, const Vec3<float>& v) {
    for (int a = 0; a < 3; ++a) init.v[std::size_t(a * n + p)] = v[a];
  };

  switch (c.scenario) {
    case StabilityScenario::FreeFallBounce:
      config.gravity = Vec3<float>(0.0f, -9.81f, 0.0f);
      s.end = 0.4;
      break;
    case StabilityScenario::CompressRelease: {
      // A slipping plate from the top down to 5 % of the height in 0.1 s, then gone.
      mpm::ColliderState plate;
      plate.shape = mpm::ColliderShape::Box;
      plate.contact = mpm::ContactType::Slip;
      plate.half_extents = Vec3<float>(0.08f, 0.02f, 0.08f);
      plate.center = Vec3<float>(centre, high[1] + plate.half_extents[1], centre);
      plate.linear_velocity = Vec3<float>(0.0f, -0.95f * kSide / 0.1f, 0.0f);
      config.colliders = {engine::ColliderSpec{plate, 0.1}};
      config.gravity = Vec3<float>(0.0f, -9.81f, 0.0f);
      s.end = 0.3;
      s.reference_time = 0.1;
      break;
    }
    case StabilityScenario::ForcedInversion: {
      // The top layer is driven 1.5 heights down, through the bottom layer, which holds still.
      const float layer = 0.5f * kDx;
      config.dirichlet = {
          engine::DirichletSpec{Vec3<float>::constant(centre), Vec3<float>::zero(), Vec3<float>::zero(), 0.1},
          engine::DirichletSpec{Vec3<float>::constant(centre), Vec3<float>(0.0f, -1.5f * kSide / 0.1f, 0.0f),
                                Vec3<float>::zero(), 0.1}};
      for (Index p = 0; p < n; ++p) {
        const float y = init.x[std::size_t(n + p)];
        if (y < low[1] + layer) init.dirichlet_group[std::size_t(p)] = 0;
        if (y > high[1] - layer) init.dirichlet_group[std::size_t(p)] = 1;
      }
      if (c.enriched) geometry::assign_corner_dirichlet_groups(init);
      s.end = 0.3;
      s.reference_time = 0.1;
      break;
    }
    case StabilityScenario::Spin:
      for (Index p = 0; p < n; ++p) {
        const Vec3<float> r(init.x[std::size_t(p)] - centre, init.x[std::size_t(n + p)] - centre,
                            init.x[std::size_t(2 * n + p)] - centre);
        set_velocity(p, cross(Vec3<float>(0.0f, 10.0f, 0.0f), r));
      }
      s.end = 0.3;
      break;
    case StabilityScenario::WallImpact:
      for (Index p = 0; p < n; ++p) set_velocity(p, Vec3<float>(50.0f, 0.0f, 0.0f));
      s.end = 0.01;
      break;
  }
  return s;
}

}  // namespace

std::string StabilityCase::name() const {
  return fmt::format("{}/E{:.0e}/nu{:.2f}/{}/{}/{}", model_name(model), youngs_modulus, poissons_ratio,
                     scenario_name(scenario), enriched ? "enriched" : "plain", implicit ? "implicit" : "explicit");
}

bool StabilityOutcome::acceptable() const {
  switch (status) {
    case Status::Finished: return std::isfinite(energy_ratio) && energy_ratio <= kStabilityEnergyBound;
    case Status::NonFinite:
    case Status::Error: return !message.empty();
    case Status::SubstepBudget:
    case Status::TimeBudget: return true;
  }
  return false;
}

const char* StabilityOutcome::status_name() const {
  switch (status) {
    case Status::Finished: return "finished";
    case Status::NonFinite: return "non-finite";
    case Status::Error: return "error";
    case Status::SubstepBudget: return "substep budget";
    case Status::TimeBudget: return "time budget";
  }
  return "?";
}

StabilityOutcome run_stability_case(const Exec& exec, const StabilityCase& c, const StabilityBudget& budget) {
  const Setup setup = build(c);
  StabilityOutcome outcome;
  outcome.end_seconds = setup.end;
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  try {
    engine::FullOrderSim sim(exec, setup.config, setup.init);
    // About 50 energy samples per case: enough to see growth, cheap beside the substeps.
    const double sample_interval = setup.end / 50.0;
    double next_sample = 0.0;
    std::optional<double> reference;
    double largest_after = 0.0;
    while (sim.time() < setup.end) {
      if (sim.steps() >= budget.max_substeps) {
        outcome.status = StabilityOutcome::Status::SubstepBudget;
        break;
      }
      if (elapsed() > budget.max_wall_seconds) {
        outcome.status = StabilityOutcome::Status::TimeBudget;
        break;
      }
      sim.substep(float(std::min<double>(sim.stable_dt(), setup.end - sim.time())));
      if (!reference && sim.time() >= setup.reference_time)
        reference = mechanical_energy(sim, setup.init, kFloorOrigin);
      if (reference && sim.time() >= next_sample) {
        largest_after = std::max(largest_after, mechanical_energy(sim, setup.init, kFloorOrigin));
        next_sample += sample_interval;
      }
    }
    if (reference) {
      largest_after = std::max(largest_after, mechanical_energy(sim, setup.init, kFloorOrigin));
      // A body at rest on the floor without elastic energy would have none to compare with; every
      // scenario starts with some.
      outcome.energy_ratio = *reference > 0.0 ? largest_after / *reference : 0.0;
    }
    outcome.simulated_seconds = sim.time();
    outcome.substeps = sim.steps();
    outcome.largest_enriched_share = sim.enrichment_statistics().largest_share;
  } catch (const engine::NonFiniteError& error) {
    outcome.status = StabilityOutcome::Status::NonFinite;
    outcome.message = error.what();
  } catch (const Error& error) {
    outcome.status = StabilityOutcome::Status::Error;
    outcome.message = error.what();
  }
  outcome.wall_seconds = elapsed();
  return outcome;
}

}  // namespace romp::analysis
