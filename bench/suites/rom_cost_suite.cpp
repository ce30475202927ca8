// rom-cost suite (ROM paper, Sec. 5.4 and Fig. 20): what one substep costs at a scene's own resolution,
// full order against reduced order, on the same device. The map has the paper's size (r = 6, 5 hidden
// layers of 30) with seeded random weights, so no sweep or training is needed and it runs at sizes whose
// full-order sweep a machine cannot afford (the tower's 3 million points: --scene scenes/rom/tower.toml
// --set dx=0.0048). Its displacements are a millimetre: the body barely deforms, so a trained map's
// Eulerian inversion may take more inversion iterations than this one's. Wall seconds per simulated second
// are a substep's median time over the run's stable step at t = 0. Each setup also records the host
// traffic (allocations, uploads, downloads) of one substep after the timed ones.
#include <fmt/format.h>

#include <functional>
#include <string>
#include <vector>

#include "bench/suites/random_map.h"
#include "bench/suites/suites.h"
#include "host/engine/full_order_sim.h"
#include "host/engine/reduced_sim.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"
#include "kernels/core/memory.h"

namespace romp::bench {
namespace {

// The reduced setups timed: the paper's real-time pair (Eulerian, velocity-only), the same with every
// inversion started from the cell's sample (no warm starts: what they save), its position-velocity variant,
// and Lagrangian velocity-only, which decodes every point to find the samples' neighbours.
struct CostCase {
  engine::RomQuadrature quadrature;
  engine::RomProjection projection;
  const char* name;
  bool warm_start = true;
  bool frame_graphs = true;  // frames as CUDA graphs where the step allows (ReducedOptions::frame_graphs)
};
constexpr CostCase kCases[] = {
    {engine::RomQuadrature::Eulerian, engine::RomProjection::Velocity, "eulerian_velocity"},
    // The same substeps launched one by one: what the frame's graph saves the host.
    {engine::RomQuadrature::Eulerian, engine::RomProjection::Velocity, "eulerian_velocity_no_graph", true, false},
    {engine::RomQuadrature::Eulerian, engine::RomProjection::Velocity, "eulerian_velocity_cold", false},
    {engine::RomQuadrature::Eulerian, engine::RomProjection::PositionVelocity, "eulerian_position"},
    {engine::RomQuadrature::Lagrangian, engine::RomProjection::Velocity, "lagrangian_velocity"},
    {engine::RomQuadrature::Lagrangian, engine::RomProjection::Velocity, "lagrangian_velocity_no_graph", true, false},
};

}  // namespace

void run_rom_cost_suite(Context& context) {
  const Options& options = context.options();
  if (options.scene.empty()) {
    fmt::print("rom-cost skipped: needs --scene SCENE.toml\n");
    return;
  }
  const scene::Scene scene = scene::load_scene(options.scene, options.parameters);
  const scene::SceneSetup setup = scene::build_scene(scene);
  const Index n = setup.particles.count();
  const rom::DeformationMapWeights map = random_map(geometry::bounds_of_planes(setup.particles.x, n));
  // The host traffic of one more call after the timed ones (buffers grown), a call running `substeps`
  // substeps: on a GPU each allocation synchronises the device, each transfer is a blocking round trip and
  // each launch costs the host microseconds outside a CUDA graph, whatever the kernels' speed.
  auto traffic_of_one = [&context](const std::string& key, int substeps, const std::function<void()>& run) {
    const memory::Traffic before = memory::traffic();
    run();
    const memory::Traffic after = memory::traffic();
    const double per_substep = 1.0 / substeps;
    context.record(key + ".allocations_per_substep", double(after.allocations - before.allocations) * per_substep);
    context.record(key + ".uploads_per_substep", double(after.uploads - before.uploads) * per_substep);
    context.record(key + ".downloads_per_substep", double(after.downloads - before.downloads) * per_substep);
    context.record(key + ".launches_per_substep", double(after.launches - before.launches) * per_substep);
    return fmt::format("{} allocations, {} uploads, {} downloads, {} launches per {} substep{}",
                       after.allocations - before.allocations, after.uploads - before.uploads,
                       after.downloads - before.downloads, after.launches - before.launches, substeps,
                       substeps == 1 ? "" : "s");
  };
  // Launches per substep by stage (on CUDA, outside a graph, each a few microseconds of the host's time).
  auto launches_by_stage = [&context](const std::string& key,
                                      const std::vector<std::pair<std::string, std::int64_t>>& table,
                                      std::int64_t substeps) {
    std::string text;
    for (const auto& [stage, count] : table) {
      const double per_substep = double(count) / double(substeps);
      text += fmt::format(" {} {:.3g}", stage, per_substep);
      context.record(fmt::format("{}.launches_per_substep.{}", key, stage), per_substep);
    }
    return text;
  };
  // The reduced substeps run as advance_to runs a frame: several, read back once after the last (ReducedSim::
  // substeps), which is what a CUDA graph of them would replay. The full-order step reads back every substep.
  constexpr int kFrameSubsteps = 8;
  fmt::print("rom-cost {}: {} material points, dx = {:.4g} m\n", options.scene, n, setup.config.dx);

  for (const Exec& exec : context.execs()) {
    engine::FullOrderSim full(exec, setup.config, setup.particles);
    const float full_dt = full.stable_dt();
    const Measurement& f = context.time(
        "rom-cost", "full_order", exec, n, "particle-substep", [&] { full.substep(full_dt); }, 0.0,
        fmt::format("{}: {} particles, dt = {:.3g} s", options.scene, n, full_dt));
    const std::string place = fmt::format("{}{}", f.backend, f.threads);
    const double full_per_second = f.median_seconds() / full_dt;
    context.record(fmt::format("rom-cost.full_order.{}.wall_per_simulated_second", place), full_per_second);
    const std::string full_key = fmt::format("rom-cost.full_order.{}", place);
    fmt::print("         full_order: launches per substep by stage:{}; host traffic: {}\n",
               launches_by_stage(full_key, full.stage_launches(), full.steps()),
               traffic_of_one(full_key, 1, [&] { full.substep(full_dt); }));

    for (const CostCase& c : kCases)
      for (const int samples : options.rom_samples) {
        engine::ReducedOptions reduced;
        reduced.quadrature = c.quadrature;
        reduced.projection = c.projection;
        reduced.samples = Index(samples);
        reduced.warm_start_inversion = c.warm_start;
        reduced.frame_graphs = c.frame_graphs ? engine::GraphReplay::Always : engine::GraphReplay::Never;
        engine::ReducedSim sim(exec, setup.config, setup.particles, map, std::vector<float>(6, 0.0f), reduced);
        const float dt = sim.stable_dt();
        const std::string name =
            fmt::format("{}_{}", c.name, samples == 0 ? std::string("all") : std::to_string(samples));
        const auto frame = [&] { sim.substeps(dt, kFrameSubsteps); };
        const Measurement& m =
            context.time("rom-cost", name, exec, kFrameSubsteps, "substep", frame, 0.0,
                         fmt::format("{} points, dt = {:.3g} s, {} substeps a read-back", n, dt, kFrameSubsteps));
        const std::string key = fmt::format("rom-cost.{}.{}", name, place);
        const double per_second = m.median_seconds() / kFrameSubsteps / dt;
        context.record(key + ".wall_per_simulated_second", per_second);
        context.record(key + ".speedup", full_per_second / per_second);
        const double quadrature_points = c.quadrature == engine::RomQuadrature::Eulerian
                                             ? double(sim.last_quadrature_count())
                                             : double(sim.lagrangian_quadrature_points()) / double(sim.steps());
        context.record(key + ".quadrature_points_per_substep", quadrature_points);
        std::string evaluations;
        if (c.quadrature == engine::RomQuadrature::Eulerian && sim.eulerian_points() > 0) {
          // What inverting g costs per point: evaluations of g, those with both Jacobians (each three
          // reverse sweeps more), and the quasi-Newton iterations.
          const double points = double(sim.eulerian_points());
          const double per_point[4] = {
              double(sim.eulerian_map_evaluations()) / points, double(sim.eulerian_jacobian_evaluations()) / points,
              double(sim.inversion_iterations()) / points, double(sim.eulerian_warm_starts()) / points};
          context.record(key + ".map_evaluations_per_eulerian_point", per_point[0]);
          context.record(key + ".jacobian_evaluations_per_eulerian_point", per_point[1]);
          context.record(key + ".inversion_iterations_per_eulerian_point", per_point[2]);
          context.record(key + ".warm_started_share", per_point[3]);
          evaluations = fmt::format(
              "; per Eulerian point and substep: {:.2f} evaluations of g ({:.2f} with the "
              "Jacobians), {:.2f} iterations, {:.0f} % warm-started",
              per_point[0], per_point[1], per_point[2], 100.0 * per_point[3]);
        }
        if (c.projection == engine::RomProjection::PositionVelocity) {
          // Each linearisation evaluates g and ∂g/∂x̂ at the samples, inside one block on CUDA.
          const double per_substep = double(sim.gauss_newton_linearisations()) / double(sim.steps());
          const double unconverged = double(sim.unconverged_projections()) / double(sim.steps());
          context.record(key + ".gauss_newton_linearisations_per_substep", per_substep);
          context.record(key + ".gauss_newton_unconverged_share", unconverged);
          evaluations += fmt::format(
              "; {:.2f} Gauss–Newton linearisations per substep, {:.0f} % of the projections "
              "unconverged",
              per_substep, 100.0 * unconverged);
        }
        std::string split;
        for (const auto& [stage, seconds] : sim.stage_seconds())
          split += fmt::format(" {} {:.3g}", stage, 1e3 * seconds / double(sim.steps()));
        const std::string launches = launches_by_stage(key, sim.stage_launches(), sim.steps());
        context.record(key + ".graph_frames", double(sim.graph_frames()));
        fmt::print(
            "         {}: {:.0f} quadrature points{}; ms per substep by stage:{}; launches per substep by stage:{}; "
            "frames as graphs: {} ({} captured); host traffic: {}\n",
            name, quadrature_points, evaluations, split, launches, sim.graph_frames(), sim.graph_captures(),
            traffic_of_one(key, kFrameSubsteps, frame));
      }
  }
}

}  // namespace romp::bench
