// step suite: full-order MPM particle-substeps per second, with memory per particle, for the
// jelly cube and the sand column of the neural-constitutive-law paper at 100k and 1M particles, with
// the portable and the tiled P2G side by side; and the jelly cube at 1k and 4k particles a frame at a time,
// its substeps in batches replayed as graphs or launched.
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "bench/suites/suites.h"
#include "host/engine/full_order_sim.h"
#include "host/geometry/sampling.h"
#include "host/scene/material_library.h"

namespace romp::bench {
namespace {

constexpr int kParticlesPerCellPerAxis = 2;

struct StepCase {
  const char* name;
  scene::NclawMaterial material;
  Vec3<float> low, high;  // the body, in the unit-cube domain
  Vec3<float> velocity;
};

// The body is resampled so that it holds about `particles` particles at 2 per cell per axis.
// The P2G kernels timed, and how often the particles are sorted by block: every substep (the H200 baseline's
// setting), and every kSortEveryOnCuda substeps with the tiled kernel (particles that left their block since
// go straight to the grid, which is built with the sort around the particles' blocks and kept until then).
// Plastic materials' return map runs in G2P but in the last variant, which runs for them alone: its own pass,
// as before the two were fused.
struct StepVariant {
  engine::P2GKernel p2g;
  int sort_every;
  const char* name;
  engine::ReturnMapPass return_map = engine::ReturnMapPass::InG2P;
};
constexpr StepVariant kVariants[] = {
    {engine::P2GKernel::Portable, 1, "portable"},
    {engine::P2GKernel::Tiled, 1, "tiled"},
    {engine::P2GKernel::Tiled, engine::kSortEveryOnCuda, "tiled_sort4"},
    {engine::P2GKernel::Tiled, engine::kSortEveryOnCuda, "tiled_sort4_return_pass", engine::ReturnMapPass::Separate},
};
static_assert(engine::kSortEveryOnCuda == 4, "the variant's name says how often it sorts");

engine::FullOrderSim make_sim(const Exec& exec, const StepCase& c, Index particles, const StepVariant& variant,
                              float fixed_dt = 0.0f, engine::GraphReplay frame_graphs = engine::GraphReplay::Auto) {
  const Vec3<float> extent = c.high - c.low;
  const float volume = extent[0] * extent[1] * extent[2];
  const float spacing = std::cbrt(volume / float(particles));
  const float dx = kParticlesPerCellPerAxis * spacing;
  engine::FullOrderConfig config;
  config.dx = dx;
  const std::int32_t cells = std::int32_t(std::ceil(1.0f / dx));
  config.domain_cells = {cells, cells, cells};
  config.materials = {scene::nclaw_material(c.material)};
  config.p2g = variant.p2g;
  config.sort_every = variant.sort_every;
  config.return_map = variant.return_map;
  config.fixed_dt = fixed_dt;
  config.frame_graphs = frame_graphs;
  const geometry::SamplingSpec lattice{geometry::SamplingMethod::Lattice, kParticlesPerCellPerAxis, dx};
  mpm::ParticleInit init = geometry::sample_box(c.low, c.high, lattice, config.materials[0].density);
  for (Index p = 0; p < init.count(); ++p)
    for (int a = 0; a < 3; ++a) init.v[a * init.count() + p] = c.velocity[a];
  return engine::FullOrderSim(exec, config, init);
}

// A scene of few particles a frame of 10 substeps at a time (advance_to): in batches replayed as graphs, and
// the same batches launched substep by substep (FullOrderSim::runs_batches). The target for such
// scenes is 50 µs a substep on a GPU; the step is the CFL step at the start, fixed so that every frame is alike.
void time_small_scenes(Context& context, const StepCase& c) {
  constexpr int kSubstepsPerFrame = 10;
  const StepVariant backends_choice{engine::P2GKernel::Tiled, 0, "tiled"};
  for (const Index particles : {Index(1000), Index(4000)})
    for (const Exec& exec : context.execs())
      for (const bool graphs : {true, false}) {
        const float dt = make_sim(exec, c, particles, backends_choice).stable_dt();
        engine::FullOrderSim sim = make_sim(exec, c, particles, backends_choice, dt,
                                            graphs ? engine::GraphReplay::Always : engine::GraphReplay::Never);
        const Index n = sim.particles().count();
        const Measurement& m = context.time(
            "step", fmt::format("{}_{}k_frames{}", c.name, particles / 1000, graphs ? "" : "_no_graph"), exec,
            n * kSubstepsPerFrame, "particle-substep",
            [&] { sim.advance_to(sim.time() + double(kSubstepsPerFrame) * double(dt)); }, 0.0,
            fmt::format("{} particles, frames of {} substeps, batches {}", n, kSubstepsPerFrame,
                        graphs ? "replayed as graphs" : "launched substep by substep"));
        const std::string where = fmt::format("step.{}.{}{}", m.name, m.backend, m.threads);
        context.record(where + ".us_per_substep", m.median_seconds() / kSubstepsPerFrame * 1e6);
        context.record(where + ".batches_replayed", double(sim.graph_batches()));
        context.record(where + ".batches_rolled_back", double(sim.rolled_back_batches()));
      }
}

}  // namespace

void run_step_suite(Context& context) {
  const StepCase cases[] = {
      {"jelly_cube", scene::NclawMaterial::Jelly, {0.25f, 0.25f, 0.25f}, {0.75f, 0.75f, 0.75f}, {1.0f, -1.5f, -2.0f}},
      {"sand_column", scene::NclawMaterial::Sand, {0.4f, 0.1f, 0.4f}, {0.6f, 0.7f, 0.6f}, {0.0f, 0.0f, 0.0f}},
  };
  for (const Index nominal : {Index(100000), Index(1000000)}) {
    const Index particles = context.scaled(nominal, 1000);
    // Enough substeps per repeat that the per-substep host work is part of what is measured.
    const int substeps = nominal >= 1000000 ? 2 : 10;
    for (const StepCase& c : cases)
      for (const Exec& exec : context.execs())
        for (const StepVariant& variant : kVariants) {
          if (variant.return_map == engine::ReturnMapPass::Separate && c.material == scene::NclawMaterial::Jelly)
            continue;  // elastic: no return map
          engine::FullOrderSim sim = make_sim(exec, c, particles, variant);
          const float dt = sim.stable_dt();
          const Index n = sim.particles().count();
          const std::string kernel = variant.name;
          const Measurement& m = context.time(
              "step", fmt::format("{}_{}k_{}", c.name, nominal / 1000, kernel), exec, n * substeps, "particle-substep",
              [&] {
            for (int s = 0; s < substeps; ++s) sim.substep(dt);
              },
              0.0, fmt::format("{} particles, dx = {:.4g} m, {} P2G", n, sim.config().dx, kernel));
          const std::string where = fmt::format("step.{}.{}{}", m.name, m.backend, m.threads);
          const double bytes = double(sim.particles().bytes() + sim.grid().bytes());
          context.record(where + ".bytes_per_particle", bytes / double(n));
          // How often it sorted (the early sorts: a particle had left the grid kept since the last one), and the
          // grid nodes per particle, which a grid kept between sorts widens.
          context.record(where + ".sorts_per_substep", double(sim.sort_statistics().sorts) / double(sim.steps()));
          context.record(where + ".early_sorts", double(sim.sort_statistics().early_sorts));
          context.record(where + ".grid_nodes_per_particle", double(sim.grid().counted_nodes(exec)) / double(n));
          // Where a substep goes, over warm-up and timed repeats together.
          double total = 0.0;
          for (const auto& [stage, seconds] : sim.stage_seconds()) total += seconds;
          for (const auto& [stage, seconds] : sim.stage_seconds())
            context.record(where + ".share." + stage, seconds / total);
        }
  }
  time_small_scenes(context, cases[0]);
}

}  // namespace romp::bench
