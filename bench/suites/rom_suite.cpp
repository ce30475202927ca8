// rom suite (ROM paper, Fig. 20 and Tables 3-6): for a scene and a model trained on its sweep, the
// full-order run and every quadrature × projection pair at 10, 50 and all sample points (or
// --rom-samples), on the same device: wall seconds per simulated second, speedup over the full-order
// run, and the accumulated position error against it. Needs --scene and --rom-model (and --set for the scene's
// parameters).
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bench/suites/suites.h"
#include "host/engine/full_order_sim.h"
#include "host/engine/reduced_sim.h"
#include "host/engine/rom_model_loader.h"
#include "host/run/position_error.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"

namespace romp::bench {
namespace {

// Frame k's time; the last frame lands on the end time (as romp run's frames do).
double frame_time(const scene::Scene& scene, std::int64_t frame) {
  return frame == scene.frame_count ? scene.end_time : double(frame) / scene.frame_rate;
}

struct ReducedCase {
  engine::RomQuadrature quadrature;
  engine::RomProjection projection;
  Index samples;  // 0: all
  std::string name() const {
    return fmt::format("{}_{}_{}", quadrature == engine::RomQuadrature::Eulerian ? "eulerian" : "lagrangian",
                       projection == engine::RomProjection::Velocity ? "velocity" : "position",
                       samples == 0 ? std::string("all") : std::to_string(samples));
  }
};

}  // namespace

void run_rom_suite(Context& context) {
  const Options& options = context.options();
  if (options.scene.empty() || options.rom_model.empty()) {
    fmt::print("rom      skipped: needs --scene SCENE.toml and --rom-model MODEL.h5\n");
    return;
  }
  const scene::Scene scene = scene::load_scene(options.scene, options.parameters);
  const scene::SceneSetup setup = scene::build_scene(scene);
  const engine::LoadedReducedModel model = engine::load_reduced_model(options.rom_model, setup.particles);
  const std::int64_t frames = scene.frame_count;
  fmt::print("rom      {}: {} material points, {} frames to t = {} s; {}\n", options.scene, setup.particles.count(),
             frames, scene.end_time, model.description);

  for (const Exec& exec : context.execs()) {
    // The reference: the full-order run's positions at every frame (the last repeat's).
    std::vector<std::vector<float>> reference;
    const Measurement full = context.time(
        "rom", "full_order", exec, frames, "frame",
        [&] {
      engine::FullOrderSim sim(exec, setup.config, setup.particles);
      reference.assign(1, sim.particles().positions_in_initial_order(exec));
      for (std::int64_t k = 1; k <= frames; ++k) {
        sim.advance_to(frame_time(scene, k));
        reference.push_back(sim.particles().positions_in_initial_order(exec));
      }
        },
        0.0, options.scene);
    const std::string place = fmt::format("{}{}", full.backend, full.threads);
    const double full_per_second = full.median_seconds() / scene.end_time;
    context.record(fmt::format("rom.full_order.{}.wall_per_simulated_second", place), full_per_second);

    std::vector<ReducedCase> cases;
    for (const engine::RomQuadrature quadrature : {engine::RomQuadrature::Lagrangian, engine::RomQuadrature::Eulerian})
      for (const engine::RomProjection projection :
           {engine::RomProjection::PositionVelocity, engine::RomProjection::Velocity})
        for (const int samples : options.rom_samples) cases.push_back({quadrature, projection, Index(samples)});
    for (const ReducedCase& c : cases) {
      engine::ReducedOptions reduced;
      reduced.quadrature = c.quadrature;
      reduced.projection = c.projection;
      reduced.samples = c.samples;
      run::PositionError error;
      // The last repeat's seconds per stage and its substeps: the per-step split the ROM issue asks for.
      std::vector<std::pair<std::string, double>> stages;
      std::int64_t substeps = 0;
      const Measurement m = context.time(
          "rom", c.name(), exec, frames, "frame",
          [&] {
        engine::ReducedSim sim(exec, setup.config, setup.particles, model.map, model.xhat, reduced);
        run::PositionErrorAccumulator accumulator;
        accumulator.add_frame(0.0, sim.decode_positions(), reference[0]);
        for (std::int64_t k = 1; k <= frames; ++k) {
          sim.advance_to(frame_time(scene, k));
          accumulator.add_frame(sim.time(), sim.decode_positions(), reference[std::size_t(k)]);
        }
        error = accumulator.result();
        stages = sim.stage_seconds();
        substeps = sim.steps();
          },
          0.0, fmt::format("{} against the full-order run", options.scene));
      const std::string key = fmt::format("rom.{}.{}", c.name(), place);
      const double per_second = m.median_seconds() / scene.end_time;
      context.record(key + ".wall_per_simulated_second", per_second);
      context.record(key + ".speedup", full_per_second / per_second);
      context.record(key + ".position_error_percent", error.percent);
      std::string split;
      for (const auto& [stage, seconds] : stages) {
        const double ms_per_substep = 1e3 * seconds / double(std::max<std::int64_t>(substeps, 1));
        context.record(fmt::format("{}.stage.{}.ms_per_substep", key, stage), ms_per_substep);
        split += fmt::format(" {} {:.3g}", stage, ms_per_substep);
      }
      fmt::print("         {} ms per substep by stage:{}\n", c.name(), split);
    }
  }
}

}  // namespace romp::bench
