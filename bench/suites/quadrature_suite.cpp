// quadrature suite: one reduced-order substep with Lagrangian quadrature (ROM paper, Alg. 3) over
// every material point against over the samples and their neighbours, for 50 samples in bodies of
// 32k and 262k points. The map has the paper's size (r = 6, 5 hidden layers of 30) with seeded random
// weights, so no training is needed; its displacements are a millimetre, so the body barely deforms.
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "bench/suites/random_map.h"
#include "bench/suites/suites.h"
#include "host/engine/reduced_sim.h"
#include "host/geometry/sampling.h"
#include "host/scene/material_library.h"

namespace romp::bench {
namespace {

constexpr int kParticlesPerCellPerAxis = 2;
constexpr Index kSamples = 50;

}  // namespace

void run_quadrature_suite(Context& context) {
  const float low = 0.25f, high = 0.75f;
  const rom::DeformationMapWeights map =
      random_map(geometry::Bounds{Vec3<double>::constant(low), Vec3<double>::constant(high)});
  for (const Index nominal : {Index(32768), Index(262144)}) {
    const Index wanted = context.scaled(nominal, 4096);
    const float spacing = std::cbrt((high - low) * (high - low) * (high - low) / float(wanted));
    engine::FullOrderConfig config;
    config.dx = kParticlesPerCellPerAxis * spacing;
    const std::int32_t cells = std::int32_t(std::ceil(1.0f / config.dx));
    config.domain_cells = {cells, cells, cells};
    config.materials = {scene::nclaw_material(scene::NclawMaterial::Jelly)};
    const geometry::SamplingSpec lattice{geometry::SamplingMethod::Lattice, kParticlesPerCellPerAxis, config.dx};
    const mpm::ParticleInit body = geometry::sample_box(Vec3<float>::constant(low), Vec3<float>::constant(high),
                                                        lattice, config.materials[0].density);
    const Index n = body.count();
    for (const Exec& exec : context.execs()) {
      double every_point = 0.0;
      for (const engine::NeighbourSearch search : {engine::NeighbourSearch::Never, engine::NeighbourSearch::Always}) {
        engine::ReducedOptions options;
        options.samples = kSamples;
        options.neighbour_search = search;
        engine::ReducedSim sim(exec, config, body, map, std::vector<float>(6, 0.0f), options);
        const float dt = sim.stable_dt();
        const std::string mode = search == engine::NeighbourSearch::Never ? "every_point" : "neighbours";
        const Measurement& m = context.time(
            "quadrature", fmt::format("lagrangian_{}k_{}", nominal / 1024, mode), exec, 1, "substep",
            [&] { sim.substep(dt); }, 0.0, fmt::format("{} points, {} samples, dx = {:.4g} m", n, kSamples, config.dx));
        const std::string where = fmt::format("quadrature.{}.{}{}", m.name, m.backend, m.threads);
        context.record(where + ".quadrature_points_per_substep",
                       double(sim.lagrangian_quadrature_points()) / double(sim.steps()));
        // Where a substep goes (kinematics holds the neighbour search), over warm-up and timed repeats.
        double total = 0.0;
        for (const auto& [stage, seconds] : sim.stage_seconds()) total += seconds;
        for (const auto& [stage, seconds] : sim.stage_seconds())
          context.record(where + ".share." + stage, seconds / total);
        if (search == engine::NeighbourSearch::Never)
          every_point = m.median_seconds();
        else
          context.record(where + ".speedup_over_every_point", every_point / m.median_seconds());
      }
    }
  }
}

}  // namespace romp::bench
