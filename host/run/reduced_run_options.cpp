// Command-line options of reduced-order runs and the construction of their simulation.
#include "host/run/reduced_run_options.h"

#include <spdlog/spdlog.h>

#include "host/engine/rom_model_loader.h"

namespace romp::run {

void add_reduced_run_options(CLI::App& run, ReducedRunOptions& options) {
  // A reduced run is fast to repeat from the start: --resume continues full-order runs only.
  CLI::Option* rom = run.add_option("--rom", options.model, "Run reduced-order with this model file (romp train-rom)")
                         ->check(CLI::ExistingFile)
                         ->excludes("--resume");
  run.add_option(
         "--quadrature", options.quadrature,
         "Reduced-order quadrature: eulerian (cost follows the samples), lagrangian (the samples' neighbours), or "
         "domains (every point through its particle domain's corners, as the full-order step on particle domains "
         "transfers: for a model trained on a scene with domains = true)")
      ->check(CLI::IsMember({"eulerian", "lagrangian", "domains"}));
  run.add_option("--projection", options.projection,
                 "Reduced-order projection: velocity (Alg. 7) or position (position-velocity, Alg. 6)")
      ->check(CLI::IsMember({"velocity", "position"}));
  run.add_option("--samples", options.samples, "Sample material points per substep (0: all)")
      ->check(CLI::NonNegativeNumber);
  run.add_option("--sample-seed", options.seed, "Seed of the samples drawn each substep");
  run.add_option("--rom-cfl", options.cfl,
                 "Reduced-order substeps' CFL number, in (0, 1], instead of the scene's time.cfl (a hyper-reduced "
                 "run may need a smaller one than the full-order runs it was trained on)")
      ->check(CLI::Range(1e-6, 1.0))
      ->needs(rom);
  run.add_flag("--no-frame-graphs", options.no_frame_graphs,
               "On CUDA, launch each substep's kernels rather than replay a frame's substeps (reduced order) or a "
               "batch of them (full order, few particles) as one CUDA graph (for comparison; the results are the "
               "same). The CPU launches them anyway: a replay saves nothing there");
}

std::unique_ptr<Simulation> make_reduced_simulation(const ReducedRunOptions& options, const Exec& exec,
                                                    const scene::SceneSetup& setup) {
  engine::LoadedReducedModel model = engine::load_reduced_model(options.model, setup.particles);
  spdlog::info("{}", model.description);
  // (Scenes with particle domains move their full-order particles through the domains' corners, which only
  // the domain quadrature shares, whatever the transfer; scenes/README.md.)
  if (!setup.particles.domains.empty() && options.quadrature != "domains")
    spdlog::warn(
        "this scene's full-order runs move their particles through particle domains, which the {} quadrature "
        "does not: reduced runs will drift from them at large stretches; --quadrature domains transfers as they "
        "do",
        options.quadrature);
  if (setup.config.transfer == mpm::Transfer::Apic && setup.particles.domains.empty())
    spdlog::warn(
        "the reduced step transfers by PIC (ROM paper, Alg. 5) and this scene's full-order runs by APIC: "
        "reduced runs will drift from them by the difference (3.3 % on the gravity cylinder); give the "
        "scene [solver] transfer = \"pic-flip\", flip_alpha = 0 for its sweep and its reduced runs");
  engine::ReducedOptions reduced;
  reduced.quadrature = options.quadrature == "eulerian"  ? engine::RomQuadrature::Eulerian
                       : options.quadrature == "domains" ? engine::RomQuadrature::Domains
                                                         : engine::RomQuadrature::Lagrangian;
  reduced.projection =
      options.projection == "velocity" ? engine::RomProjection::Velocity : engine::RomProjection::PositionVelocity;
  reduced.samples = options.samples;
  reduced.seed = options.seed;
  spdlog::info("reduced-order run: {} quadrature, {} projection, {} samples per substep", options.quadrature,
               options.projection, options.samples == 0 ? std::string("all") : std::to_string(options.samples));
  reduced.cfl = options.cfl;
  if (options.no_frame_graphs) reduced.frame_graphs = engine::GraphReplay::Never;
  if (options.cfl > 0.0)
    spdlog::info("reduced substeps at CFL number {} (the scene's: {})", options.cfl, setup.config.cfl);
  return reduced_simulation(exec, setup.config, setup.particles, std::move(model.map), std::move(model.xhat), reduced);
}

}  // namespace romp::run
