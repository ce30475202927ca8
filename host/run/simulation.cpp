// The full-order and reduced-order engines behind the Simulation interface of the frame loop.
#include "host/run/simulation.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "host/engine/full_order_sim.h"

namespace romp::run {
namespace {

class FullOrderRun final : public Simulation {
 public:
  FullOrderRun(const Exec& exec, const engine::FullOrderConfig& config, const mpm::ParticleInit& particles)
      : sim_(exec, config, particles) {}

  engine::FullOrderSim& sim() { return sim_; }
  bool advance_to(double t, const std::function<bool()>& stop) override { return sim_.advance_to(t, stop); }
  io::FrameData capture() override {
    io::FrameData frame;
    frame.time = sim_.time();
    frame.step = sim_.steps();
    // Read through the const view: the particles stay as they are (and the next step keeps its speed).
    const mpm::ParticleSet& particles = std::as_const(sim_).particles();
    frame.x = particles.positions_in_initial_order(sim_.exec());
    frame.v = particles.velocities_in_initial_order(sim_.exec());
    frame.F = particles.deformation_gradients_in_initial_order(sim_.exec());
    frame.C = particles.affine_velocities_in_initial_order(sim_.exec());
    const std::vector<float> plastic = particles.plastic_state_in_initial_order(sim_.exec());
    if (!plastic.empty()) {
      const std::size_t n = plastic.size() / 2;
      frame.Jp.assign(plastic.begin(), plastic.begin() + std::ptrdiff_t(n));
      frame.plastic_strain.assign(plastic.begin() + std::ptrdiff_t(n), plastic.end());
    }
    return frame;
  }
  void track_points(const std::vector<float>& X, engine::TracerCarrier carrier) override {
    sim_.set_tracers(X, carrier);
  }
  io::FrameData capture_points() override {
    io::FrameData frame;
    frame.time = sim_.time();
    frame.step = sim_.steps();
    frame.x = sim_.tracer_positions_on_host();
    frame.v = sim_.tracer_velocities_on_host();
    return frame;
  }
  io::FieldMask point_fields() const override { return io::kFieldX | io::kFieldV; }
  double time() const override { return sim_.time(); }
  std::int64_t steps() const override { return sim_.steps(); }
  std::vector<std::pair<std::string, double>> stage_seconds() const override { return sim_.stage_seconds(); }
  DomainState domain_state() override {
    if (!sim_.domains()) return {};
    return {sim_.domains()->corner_positions_on_host(sim_.exec()), sim_.domains()->stiffening(sim_.exec()),
            std::as_const(sim_).particles().domains_in_initial_order(sim_.exec())};
  }
  bool resumable() const override { return true; }
  std::vector<std::string> diagnostics() const override {
    std::vector<std::string> lines;
    const engine::EnrichmentStatistics& enrichment = sim_.enrichment_statistics();
    if (enrichment.substeps > 0)
      lines.push_back(
          fmt::format("enrichment: {:.1f}% of domain particles per substep on average, {:.1f}% at most (step {})",
                      100.0 * enrichment.share_sum / double(enrichment.substeps), 100.0 * enrichment.largest_share,
                      enrichment.largest_share_step));
    if (sim_.runs_batches())
      lines.push_back(fmt::format(
          "full-order substeps in batches read back once each: {}; {} went back to their start (a speed outran "
          "the planned step, or a stage failed) and ran substep by substep",
          sim_.graph_batches() > 0 || sim_.replays_batch_graphs()
              ? fmt::format("{} replayed as one graph ({} captured)", sim_.graph_batches(), sim_.graph_captures())
              : std::string("launched substep by substep (graphs off: on the CPU by default, where a replay saves "
                            "nothing)"),
          sim_.rolled_back_batches()));
    const engine::ImplicitSolveTotals* totals = sim_.implicit_totals();
    if (totals != nullptr && totals->solves > 0)
      lines.push_back(
          fmt::format("implicit solve: {} solves, {:.1f} CG iterations on average ({} at most), {} did not "
                      "converge and kept the explicit velocities",
                      totals->solves, double(totals->iterations) / double(totals->solves), totals->most_iterations,
                      totals->not_converged));
    return lines;
  }

 private:
  engine::FullOrderSim sim_;
};

class ReducedRun final : public Simulation {
 public:
  ReducedRun(const Exec& exec, const engine::FullOrderConfig& config, const mpm::ParticleInit& particles,
             rom::DeformationMapWeights map, std::vector<float> xhat, const engine::ReducedOptions& options)
      : sim_(exec, config, particles, std::move(map), std::move(xhat), options), X_(particles.x) {}

  bool advance_to(double t, const std::function<bool()>& stop) override { return sim_.advance_to(t, stop); }
  io::FrameData capture() override { return decoded_at(X_); }
  // Decoded by the map: nothing carries them.
  void track_points(const std::vector<float>& X, engine::TracerCarrier) override { points_X_ = X; }
  io::FrameData capture_points() override { return decoded_at(points_X_); }
  io::FieldMask point_fields() const override { return io::kFieldX | io::kFieldV | io::kFieldF | io::kFieldC; }
  double time() const override { return sim_.time(); }
  std::int64_t steps() const override { return sim_.steps(); }
  std::vector<std::pair<std::string, double>> stage_seconds() const override { return sim_.stage_seconds(); }
  bool resumable() const override { return false; }
  std::vector<std::string> diagnostics() const override {
    std::vector<std::string> lines;
    lines.push_back(
        fmt::format("reduced-order: {} substeps, {} position projections stopped unconverged; largest "
                    "CFL number {:.3g} (the step follows the speeds of the frame before)",
                    sim_.steps(), sim_.unconverged_projections(), sim_.largest_cfl_number()));
    lines.push_back(sim_.runs_frame_graphs()
                        ? fmt::format("reduced-order frames: {} replayed as one graph each ({} captured)",
                                      sim_.graph_frames(), sim_.graph_captures())
                        : std::string("reduced-order frames: launched substep by substep (graphs off: on the CPU "
                                      "by default, where a replay saves nothing; or their build needs the host)"));
    if (sim_.searches_neighbours() && sim_.steps() > 0)
      lines.push_back(
          fmt::format("Lagrangian quadrature: the samples and their neighbours, {:.0f} of {} material "
                      "points per substep on average",
                      double(sim_.lagrangian_quadrature_points()) / double(sim_.steps()), X_.size() / 3));
    if (sim_.domain_corners() > 0)
      lines.push_back(
          fmt::format("domain quadrature: every material point through its particle domain, {} "
                      "corners placed by the map per substep",
                      sim_.domain_corners()));
    const std::int64_t points =
        sim_.quadrature_points_used() + sim_.quadrature_points_outside() + sim_.quadrature_points_unconverged();
    if (points > 0)
      lines.push_back(fmt::format(
          "Eulerian quadrature: {} points, {} used, {} outside the body, {} whose inversion "
          "of g did not converge; {} inversion iterations ({:.2f} per point used), {} started from their "
          "place's last solution",
          points, sim_.quadrature_points_used(), sim_.quadrature_points_outside(), sim_.quadrature_points_unconverged(),
          sim_.inversion_iterations(),
          double(sim_.inversion_iterations()) / double(std::max<std::int64_t>(sim_.quadrature_points_used(), 1)),
          sim_.eulerian_warm_starts()));
    return lines;
  }

 private:
  io::FrameData decoded_at(const std::vector<float>& X) {
    engine::ReducedSim::DecodedState state = sim_.decode(X);
    io::FrameData frame;
    frame.time = sim_.time();
    frame.step = sim_.steps();
    frame.C.assign(3 * state.x.size(), 0.0f);
    frame.x = std::move(state.x);
    frame.v = std::move(state.v);
    frame.F = std::move(state.F);
    return frame;
  }

  engine::ReducedSim sim_;
  std::vector<float> X_;         // the material points' reference positions
  std::vector<float> points_X_;  // track_points' points
};

}  // namespace

std::unique_ptr<Simulation> full_order_simulation(const Exec& exec, const engine::FullOrderConfig& config,
                                                  const mpm::ParticleInit& particles, double time, std::int64_t steps) {
  auto run = std::make_unique<FullOrderRun>(exec, config, particles);
  run->sim().restore_clock(time, steps);
  return run;
}

std::unique_ptr<Simulation> reduced_simulation(const Exec& exec, const engine::FullOrderConfig& config,
                                               const mpm::ParticleInit& particles, rom::DeformationMapWeights map,
                                               std::vector<float> xhat, const engine::ReducedOptions& options) {
  return std::make_unique<ReducedRun>(exec, config, particles, std::move(map), std::move(xhat), options);
}

}  // namespace romp::run
