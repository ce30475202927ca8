// The frame loop of a full-order run: setup, resume, substeps to each frame time, capture, and the
// hand-off of each frame to the I/O worker.
#include "host/run/scene_runner.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include "host/build_info.h"
#include "host/engine/full_order_sim.h"
#include "host/run/frame_outputs.h"
#include "host/run/interrupt.h"
#include "host/run/progress.h"
#include "host/run/simulation.h"
#include "host/scene/scene_setup.h"
#include "host/scene/toml_reader.h"
#include "kernels/core/memory.h"
#include "nn/io/checkpoint.h"
#include "nn/io/io_worker.h"
#include "nn/io/obj_export.h"
#include "nn/io/output_lock.h"
#include "nn/io/snapshot_layout.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/snapshot_writer.h"
#include "nn/io/unusable_file_error.h"

namespace romp::run {
namespace {

namespace fs = std::filesystem;

// Frames waiting for the I/O worker: enough to hide a slow write behind the next frame's substeps,
// few enough that a fast simulation cannot pile up frames in memory.
constexpr std::size_t kQueuedFrames = 2;

// The header of the run's snapshot: the material points' reference state is `particles`', or that of
// the snapshot `output_points` when the frames are written at its points.
io::SnapshotHeader snapshot_header(const scene::Scene& scene, const mpm::ParticleInit& particles,
                                   const std::string& output_points) {
  io::SnapshotHeader header;
  if (output_points.empty()) {
    header.X = particles.x;
    header.mass = particles.mass;
    header.volume0 = particles.volume0;
    header.material = particles.material;
    header.group = particles.dirichlet_group;
  } else {
    io::SnapshotHeader points;
    try {
      points = io::SnapshotReader(output_points).header();
    } catch (const Error& error) {
      throw scene::SceneError(fmt::format("--output-points: {}", error.what()));
    }
    // The points are carried or decoded from their reference positions: a non-finite one (an all-NaN
    // snapshot) would write NaN frames, and one outside the domain has no grid to ride on.
    const std::size_t n = points.X.size() / 3;
    for (int a = 0; a < 3; ++a)
      for (std::size_t p = 0; p < n; ++p) {
        const float X = points.X[std::size_t(a) * n + p];
        const double size = double(scene.domain_cells[a]) * scene.dx;
        if (!(X >= 0.0f && double(X) <= size))
          throw scene::SceneError(
              fmt::format("--output-points {}: point {} has X[{}] = {}, outside the domain [0, {:.6g}] m "
                          "(or not finite)",
                          output_points, p, a, X, size));
      }
    header.X = points.X;
    header.mass = points.mass;
    header.volume0 = points.volume0;
    header.material = points.material;
  }
  header.scene = scene.resolved_text;
  for (const auto& [name, value] : scene.parameters) {
    header.parameter_names.push_back(name);
    header.parameter_values.push_back(value);
  }
  const BuildInfo build = build_info();
  header.romp_version = build.version;
  header.commit = build.commit;
  return header;
}

// Frame k's time; the last frame lands exactly on the scene's end time.
double frame_time(const scene::Scene& scene, std::int64_t frame) {
  return frame == scene.frame_count ? scene.end_time : double(frame) / scene.frame_rate;
}

}  // namespace

RunResult run_scene(const Exec& exec, const scene::Scene& scene, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RunResult result;
  const std::string output = options.output.empty() ? scene.output.file : options.output;
  io::FieldMask fields = io::parse_fields(scene.output.fields);
  const bool ply = scene.output.ply || options.ply;
  const std::string checkpoint_file = io::checkpoint_path(output);
  // Checked before the first substep: a folder here once failed only when the finished run was renamed.
  if (fs::is_directory(output))
    throw scene::SceneError(fmt::format("{}: the output is a folder; a run writes a snapshot file (.h5)", output));
  // Held until the run returns: a second run (or --resume) of the same output is refused, not interleaved.
  const io::OutputLock output_lock(output);

  if (options.resume && options.make_reduced)
    throw Error("--resume continues full-order runs; a reduced-order run is fast to repeat from the start");
  const bool at_points = !options.output_points.empty();
  if (options.resume && at_points)
    throw Error("--resume continues runs of the scene's material points; a checkpoint holds no tracers");
  scene::SceneSetup setup = scene::build_scene(scene);
  if (!options.frame_graphs) setup.config.frame_graphs = engine::GraphReplay::Never;
  const io::SnapshotHeader header = snapshot_header(scene, setup.particles, options.output_points);
  result.particles = setup.particles.count();

  const bool unfinished = fs::exists(io::partial_path(output)) && fs::exists(checkpoint_file);
  if (options.resume && !unfinished && fs::exists(output)) {
    spdlog::info("{} is complete; nothing to resume", output);
    result.output = output;
    result.last_frame = scene.frame_count;
    return result;
  }
  std::unique_ptr<io::SnapshotWriter> writer;
  std::int64_t first_frame = 0;
  double restored_time = 0.0;
  std::int64_t restored_steps = 0;
  if (options.resume && unfinished) {
    const io::Checkpoint checkpoint = io::read_checkpoint(checkpoint_file);
    if (checkpoint.tag != scene.resolved_text)
      throw scene::SceneError(fmt::format("{}: the scene differs from the one that wrote {}; run it without --resume",
                                          scene.source_file, checkpoint_file));
    mpm::ParticleInit& init = setup.particles;
    init.x = checkpoint.state.x;
    init.v = checkpoint.state.v;
    init.F = checkpoint.state.F;
    init.C = checkpoint.state.C;
    if (!init.plastic.empty()) {
      if (checkpoint.state.Jp.size() != std::size_t(init.count()))
        throw io::UnusableFileError(
            fmt::format("{}: holds no plastic state for the scene's {} particles", checkpoint_file, init.count()));
      init.plastic = checkpoint.state.Jp;
      init.plastic.insert(init.plastic.end(), checkpoint.state.plastic_strain.begin(),
                          checkpoint.state.plastic_strain.end());
    }
    if (!init.domains.empty()) {
      if (checkpoint.corner_x.size() != 3 * std::size_t(init.domains.corner_count()))
        throw io::UnusableFileError(
            fmt::format("{}: holds {} domain corner positions, the scene's domains have {} corners", checkpoint_file,
                        checkpoint.corner_x.size() / 3, init.domains.corner_count()));
      init.domains.resumed_corner_x = checkpoint.corner_x;
      init.domains.stiffening = checkpoint.domain_stiffening;
      init.domain = checkpoint.particle_domain;  // with the ones released since the start
    }
    first_frame = checkpoint.frame;
    restored_time = checkpoint.state.time;
    restored_steps = checkpoint.state.step;
    writer =
        std::make_unique<io::SnapshotWriter>(io::SnapshotWriter::resume(output, header, fields, first_frame + 1, ply));
    spdlog::info("resuming {} after frame {} (t = {} s)", output, first_frame, restored_time);
  } else {
    if (options.resume) spdlog::info("no unfinished run of {} to resume; starting at frame 0", output);
  }

  const std::unique_ptr<Simulation> simulation =
      options.make_reduced ? options.make_reduced(exec, setup)
                           : full_order_simulation(exec, setup.config, setup.particles, restored_time, restored_steps);
  Simulation& sim = *simulation;
  if (at_points) {
    sim.track_points(header.X, options.tracers_by);
    // x always; of the rest, what the scene asks for and the engine has at such points.
    fields = io::kFieldX | (fields & sim.point_fields());
  }
  const bool checkpoints = sim.resumable() && !at_points;
  // Frames of the material points carry their totals and the derived fields the scene asks for; frames
  // at other points have no mass or material to take them from.
  std::optional<FrameOutputs> frame_outputs;
  if (at_points) {
    if (fields & (io::kDerivedFields | io::kPlasticFields))
      spdlog::warn("output.fields {} are not written at --output-points (points without mass or material)",
                   fmt::join(io::field_names(fields & (io::kDerivedFields | io::kPlasticFields)), ", "));
    fields &= ~(io::kDerivedFields | io::kPlasticFields);
  } else {
    try {
      frame_outputs.emplace(fields, setup.config, setup.particles);
    } catch (const Error& error) {
      throw scene::SceneError(fmt::format("{}: {}", scene.source_file, error.what()));
    }
  }
  if (!writer) writer = std::make_unique<io::SnapshotWriter>(output, header, fields, ply);
  result.first_frame = first_frame;

  // The I/O worker owns the writer's calls from here on: frames (with their PLY files) and
  // checkpoints are written while the next frame is simulated.
  io::IoWorker worker(kQueuedFrames);
  double output_seconds = 0.0;
  auto hand_off = [&](std::int64_t frame) {
    const auto t0 = std::chrono::steady_clock::now();
    // Only the full-order engine has domain corners; a reduced run of the scene writes no meshes.
    const bool domains = !setup.particles.domains.empty() && !options.make_reduced;
    auto domain_state = std::make_shared<const DomainState>(
        domains && (checkpoints || !setup.embedded_meshes.empty()) ? sim.domain_state() : DomainState{});
    if (!domain_state->corner_x.empty()) {
      for (const geometry::EmbeddedMesh& mesh : setup.embedded_meshes) {
        auto vertices = std::make_shared<const std::vector<Vec3<double>>>(
            mesh.deformed(setup.particles.domains, domain_state->corner_x));
        worker.submit([&output, &mesh, vertices, frame, &scene] {
          io::write_obj(io::mesh_frame_path(output, mesh.name, frame), *vertices, mesh.triangles,
                        fmt::format("{} frame {}: {} embedded in its particle domains", scene.name, frame, mesh.name));
        });
      }
    }
    auto state = std::make_shared<io::FrameData>(at_points ? sim.capture_points() : sim.capture());
    worker.submit([&writer, state, frame, &checkpoint_file, &scene, checkpoints, domain_state, &frame_outputs] {
      if (frame_outputs) frame_outputs->add_to(*state);
      writer->append_frame(*state);
      if (checkpoints)
        io::write_checkpoint(checkpoint_file, io::Checkpoint{*state, frame, scene.resolved_text, domain_state->corner_x,
                                                             domain_state->particle_domain, domain_state->stiffening});
    });
    output_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };

  install_interrupt_handler();
  if (first_frame == 0) hand_off(0);
  result.last_frame = first_frame;
  ProgressBar progress(first_frame, scene.frame_count, scene.end_time);
  const std::int64_t steps_before = sim.steps();
  const memory::Traffic traffic_before = memory::traffic();
  for (std::int64_t frame = first_frame + 1; frame <= scene.frame_count; ++frame) {
    try {
      // An interrupt stops the run at the next substep, not at the end of the frame: the frame under way
      // is dropped, and the frames before it (with the last one's checkpoint) stay to resume from.
      if (!sim.advance_to(frame_time(scene, frame), interrupt_requested)) {
        result.interrupted = true;
        break;
      }
    } catch (const engine::NonFiniteError& error) {
      if (options.progress) progress.finish();
      worker.drain();
      throw engine::NonFiniteError(
          fmt::format("{}; frames 0..{} are in {}", error.what(), frame - 1, io::partial_path(output)), error.step(),
          error.stage(), error.index());
    }
    hand_off(frame);
    ++result.frames_written;
    result.last_frame = frame;
    if (options.progress) progress.update(frame, sim.time());
    const bool last = frame == scene.frame_count;
    if (!last && (interrupt_requested() || frame == options.stop_at_frame)) {
      result.interrupted = true;
      break;
    }
  }
  if (options.progress) progress.finish();
  worker.drain();
  if (result.interrupted) {
    result.output_in_progress = io::partial_path(output);
  } else {
    writer->finish();
    if (checkpoints) fs::remove(checkpoint_file);
    result.output = output;
  }
  result.substeps = sim.steps() - steps_before;
  result.simulated_seconds = sim.time() - restored_time;
  result.stage_seconds = sim.stage_seconds();
  result.diagnostics = sim.diagnostics();
  if (result.substeps > 0) {
    // What the loop cost the host besides its kernels (on a GPU each allocation synchronises the
    // device, each transfer is a blocking round trip and each launch a few microseconds of the host's
    // time): the first thing to read when a run is slow.
    const memory::Traffic traffic = memory::traffic();
    const double substeps = double(result.substeps);
    result.diagnostics.push_back(
        fmt::format("host traffic per substep, frame output included: {:.2f} allocations, {:.2f} uploads, {:.2f} "
                    "downloads, {:.1f} launches",
                    double(traffic.allocations - traffic_before.allocations) / substeps,
                    double(traffic.uploads - traffic_before.uploads) / substeps,
                    double(traffic.downloads - traffic_before.downloads) / substeps,
                    double(traffic.launches - traffic_before.launches) / substeps));
  }
  result.stage_seconds.emplace_back("output", output_seconds);
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace romp::run
