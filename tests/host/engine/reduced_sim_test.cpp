// ReducedSim against the full-order MPM on a motion its map represents exactly: an elastic cube that
// falls and drifts without deforming, under the translation family g(X; x̂) = X + x̂ (r = 3). The
// full-order run stays a translation to rounding (uniform velocity, C = 0, F = I), so the ROM must
// reproduce it with either projection, with every point or a few samples.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "host/engine/reduced_sim.h"
#include "host/scene/material_library.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/bspline.h"
#include "tests/host/mpm_test_scenes.h"
#include "tests/host/rom_test_maps.h"
#include "tests/support/replay_match.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

constexpr float kDx = 1.0f / 32.0f;
constexpr float kDt = 1e-3f;
constexpr int kSteps = 40;
const Vec3<float> kInitialVelocity(0.5f, 0.0f, -0.25f);

engine::FullOrderConfig falling_config() {
  engine::FullOrderConfig config = test::open_space_config(kDx, 32, scene::nclaw_material(scene::NclawMaterial::Jelly));
  config.gravity = Vec3<float>(0.0f, -9.81f, 0.0f);
  return config;
}

mpm::ParticleInit cube() {
  mpm::ParticleInit init =
      test::lattice_box(Vec3<float>::constant(0.375f), Vec3<float>::constant(0.625f), kDx, 2, 1000.0f);
  for (Index p = 0; p < init.count(); ++p) test::set_plane_vector(init.v, init.count(), p, kInitialVelocity);
  return init;
}

// cube() with every particle's lattice cell as its domain.
mpm::ParticleInit cube_with_domains() {
  mpm::ParticleInit init =
      test::lattice_box_with_domains(Vec3<float>::constant(0.375f), Vec3<float>::constant(0.625f), kDx, 2, 1000.0f);
  for (Index p = 0; p < init.count(); ++p) test::set_plane_vector(init.v, init.count(), p, kInitialVelocity);
  return init;
}

// The reference trajectory, run once per test binary.
const std::vector<float>& full_order_positions() {
  static const std::vector<float> positions = [] {
    engine::FullOrderSim sim(test::exec(), falling_config(), cube());
    for (int s = 0; s < kSteps; ++s) sim.substep(kDt);
    return sim.particles().positions_in_initial_order(sim.exec());
  }();
  return positions;
}

std::vector<float> reduced_positions(const engine::ReducedOptions& options) {
  engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, options);
  for (int s = 0; s < kSteps; ++s) sim.substep(kDt);
  EXPECT_EQ(sim.unconverged_projections(), 0);
  return sim.decode_positions();
}

float largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  float largest = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::fabs(a[i] - b[i]));
  return largest;
}

// Float rounding of 40 position updates near 0.5 m (ulp 6e-8) and of the grid's momentum / mass.
constexpr float kTrajectoryTolerance = 2e-6f;

TEST(ReducedSim, VelocityProjectionReproducesTheFullOrderTranslation) {
  const std::vector<float>& full = full_order_positions();
  const std::vector<float> reduced = reduced_positions({});
  // The cube drifted 2 cm along x (and fell 8 mm); the trajectories agree to rounding.
  EXPECT_NEAR(full[0] - cube().x[0], kInitialVelocity[0] * kSteps * kDt, 1e-4f);
  EXPECT_LT(largest_difference(full, reduced), kTrajectoryTolerance);
}

TEST(ReducedSim, PositionVelocityProjectionReproducesTheFullOrderTranslation) {
  engine::ReducedOptions options;
  options.projection = engine::RomProjection::PositionVelocity;
  EXPECT_LT(largest_difference(full_order_positions(), reduced_positions(options)), kTrajectoryTolerance);
}

// Domains are the full-order engine's: a reference whose particles have them runs the same reduced
// trajectory as one without.
TEST(ReducedSim, ParticleDomainsOfTheReferenceAreIgnored) {
  engine::ReducedSim sim(test::exec(), falling_config(), cube_with_domains(), test::translation_map(),
                         {0.0f, 0.0f, 0.0f}, {});
  for (int s = 0; s < kSteps; ++s) sim.substep(kDt);
  // Equal up to the order in which threads' float atomics sum (seen under a loaded ctest: 3e-8 m).
  EXPECT_LE(largest_difference(sim.decode_positions(), reduced_positions({})), 1e-6f);
}

// The domain quadrature on the same translation: the full-order step on particle domains keeps it, and so
// does the reduced step through the domains' corners, with every point or a few samples.
TEST(ReducedSim, DomainQuadratureReproducesTheFullOrderTranslationOnDomains) {
  const mpm::ParticleInit with_domains = cube_with_domains();
  engine::FullOrderSim full(test::exec(), falling_config(), with_domains);
  for (int s = 0; s < kSteps; ++s) full.substep(kDt);
  const std::vector<float> expected = full.particles().positions_in_initial_order(full.exec());
  for (const Index samples : {Index(0), Index(10)}) {
    engine::ReducedOptions options;
    options.quadrature = engine::RomQuadrature::Domains;
    options.samples = samples;
    engine::ReducedSim sim(test::exec(), falling_config(), with_domains, test::translation_map(), {0.0f, 0.0f, 0.0f},
                           options);
    for (int s = 0; s < kSteps; ++s) sim.substep(kDt);
    EXPECT_LT(largest_difference(expected, sim.decode_positions()), kTrajectoryTolerance) << samples << " samples";
    EXPECT_EQ(sim.lagrangian_quadrature_points(), kSteps * with_domains.count());  // every point, through its domain
  }
  // A body without domains has none to transfer through.
  engine::ReducedOptions options;
  options.quadrature = engine::RomQuadrature::Domains;
  EXPECT_THROW(
      engine::ReducedSim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, options),
      Error);
}

// As the full-order step on particle domains, the domain quadrature's CFL step follows its stiffest domain: a
// body stretched to twice its length along x (F = diag(2, 1, 1): ‖cof F‖² / 3 = 3) takes a step √3 times
// shorter than at rest, which the Lagrangian quadrature's step (the wave speed at rest) does not see; and
// where corners may enrich, it is that of a domain's edge (half a cell here), not a cell's.
TEST(ReducedSim, DomainQuadratureStepsFollowTheStiffestDomain) {
  Mat3<float> stretch = Mat3<float>::zero();
  stretch(0, 0) = 1.0f;
  engine::FullOrderConfig config = falling_config();
  config.gravity = Vec3<float>::zero();
  config.max_dt = 1.0f;  // the CFL step alone
  auto stable_dt = [&](engine::RomQuadrature quadrature) {
    engine::ReducedOptions options;
    options.quadrature = quadrature;
    mpm::ParticleInit body = cube_with_domains();
    std::fill(body.v.begin(), body.v.end(), 0.0f);
    engine::ReducedSim sim(test::exec(), config, body,
                           test::strained_translation_map(stretch, Vec3<float>::constant(0.5f)), {0.0f, 0.0f, 0.0f},
                           options);
    const float at_rest = sim.stable_dt();
    sim.substep(1e-7f);  // the body barely moves: its speed stays far below the wave speed
    EXPECT_EQ(sim.stable_dt() <= at_rest, true);
    const float stretched = sim.stable_dt();
    // A substep at that step runs at the scene's CFL number, measured with the same length and stiffening.
    sim.substep(stretched);
    EXPECT_NEAR(sim.largest_cfl_number(), config.cfl, 1e-5 * config.cfl);
    return std::pair<float, float>(at_rest, stretched);
  };
  const auto [rest_domains, stretched_domains] = stable_dt(engine::RomQuadrature::Domains);
  const auto [rest_points, stretched_points] = stable_dt(engine::RomQuadrature::Lagrangian);
  EXPECT_NEAR(rest_domains / rest_points, 0.5f, 1e-6f);
  EXPECT_NEAR(stretched_points / rest_points, 1.0f, 1e-3f);
  EXPECT_NEAR(stretched_domains / rest_domains, 1.0f / std::sqrt(3.0f), 1e-3f);
}

TEST(ReducedSim, TenSamplesFollowTheSameTrajectoryAsEveryPoint) {
  engine::ReducedOptions hyper;
  hyper.samples = 10;
  hyper.seed = 3;
  EXPECT_LT(largest_difference(reduced_positions({}), reduced_positions(hyper)), kTrajectoryTolerance);
}

// x̂ after ten substeps of deformed_body (stress everywhere), and the last substep's quadrature points.
struct NeighbourRun {
  std::vector<float> xhat;
  Index quadrature_points = 0;
  std::int64_t newton_steps = 0;
};
// 3 samples (seeded) in a 32,768-point body under a map that deforms it.
engine::ReducedSim deformed_body(engine::RomQuadrature quadrature, engine::NeighbourSearch search,
                                 engine::RomProjection projection = engine::RomProjection::Velocity,
                                 bool frame_graphs = true) {
  const mpm::ParticleInit body =
      test::lattice_box(Vec3<float>::constant(0.25f), Vec3<float>::constant(0.75f), kDx, 2, 1000.0f);
  engine::ReducedOptions options;
  options.quadrature = quadrature;
  options.samples = 3;
  options.seed = 5;
  options.neighbour_search = search;
  options.projection = projection;
  options.frame_graphs = frame_graphs ? engine::GraphReplay::Always : engine::GraphReplay::Never;
  return engine::ReducedSim(test::exec(), falling_config(), body, test::small_nonlinear_map(0.25f, 0.5f, 0.003f),
                            {0.0f, 0.0f, 0.0f}, options);
}
NeighbourRun run_deformed_body(engine::RomQuadrature quadrature, engine::NeighbourSearch search) {
  engine::ReducedSim sim = deformed_body(quadrature, search);
  EXPECT_EQ(sim.searches_neighbours(),
            quadrature == engine::RomQuadrature::Lagrangian && search == engine::NeighbourSearch::Always);
  for (int s = 0; s < 10; ++s) sim.substep(kDt);
  return {sim.xhat(), sim.last_quadrature_count(), sim.inversion_iterations()};
}

// The same x̂ from the samples' neighbours as from every point. The sums at the samples' nodes may take
// other orders (threads' atomics): rounding only; leaving out the Lagrangian neighbours two nodes away
// changes x̂ by 3-200 %.
void expect_same_xhat(const std::vector<float>& neighbours, const std::vector<float>& every) {
  float change = 0.0f;
  for (int j = 0; j < 3; ++j) change = std::max(change, std::fabs(every[j]));
  EXPECT_GT(change, 3e-4f);  // x̂ moved (the body fell 0.5 mm): the comparison is not of two resting states
  // Rounding is relative to x̂'s size, not to each coordinate's (one of them stays near 0).
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(neighbours[j], every[j], 1e-5f * change) << j;
}

// Alg. 3's neighbour search gives the samples the P2G of every material point, from a fraction of them.
TEST(ReducedSim, NeighbourQuadratureFollowsEveryPointQuadrature) {
  const NeighbourRun every = run_deformed_body(engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Never);
  const NeighbourRun neighbours = run_deformed_body(engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Always);
  EXPECT_EQ(every.quadrature_points, 32768);
  EXPECT_GT(neighbours.quadrature_points, 0);
  EXPECT_LT(neighbours.quadrature_points, 32768 / 4);  // 3 samples reach a few hundred of the points
  expect_same_xhat(neighbours.xhat, every.xhat);
}

// Of the Eulerian points of the cells near the samples, those whose stencils miss every sample's nodes
// change nothing the samples read: inverting only the others (about 60 % at ℓ = 2) keeps x̂.
TEST(ReducedSim, EulerianQuadratureInvertsOnlyTheSamplesNeighbours) {
  const NeighbourRun every = run_deformed_body(engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Never);
  const NeighbourRun neighbours = run_deformed_body(engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Auto);
  // ℓ = 2: per axis 10 of the 12 points of a sample's 6 cells reach its nodes, (10/12)³ = 58 %.
  EXPECT_LE(every.quadrature_points, 3 * 6 * 6 * 6 * 8);
  EXPECT_LT(neighbours.quadrature_points, every.quadrature_points * 2 / 3);
  EXPECT_GT(neighbours.quadrature_points, every.quadrature_points / 2);
  EXPECT_GT(neighbours.newton_steps, 0);
  EXPECT_LT(neighbours.newton_steps, every.newton_steps);  // the dropped points were inverted too
  expect_same_xhat(neighbours.xhat, every.xhat);
}

// What a frame of substeps read back once costs the host once its buffers have grown (memory::traffic
// counts it on either backend). On a GPU every allocation synchronises the device and every transfer is a
// blocking round trip: at the real-time step of the paper's tower (0.255 ms) a few dozen of either would
// use it all (bench/results/gpu-notes.md), and one would keep the substeps from running as a CUDA graph.
constexpr int kFrameSubsteps = 6;
struct FrameTraffic {
  int allocating_frames = 0;
  std::int64_t largest_uploads = 0, largest_downloads = 0, launches = 0;
};
FrameTraffic frame_traffic(engine::RomQuadrature quadrature, engine::NeighbourSearch search,
                           engine::RomProjection projection = engine::RomProjection::Velocity,
                           bool frame_graphs = false) {
  engine::ReducedSim sim = deformed_body(quadrature, search, projection, frame_graphs);
  sim.substeps(kDt, 3);
  FrameTraffic traffic;
  for (int f = 0; f < 3; ++f) {
    const memory::Traffic before = memory::traffic();
    sim.substeps(kDt, kFrameSubsteps);
    const memory::Traffic after = memory::traffic();
    traffic.allocating_frames += after.allocations > before.allocations;
    traffic.largest_uploads = std::max(traffic.largest_uploads, after.uploads - before.uploads);
    traffic.largest_downloads = std::max(traffic.largest_downloads, after.downloads - before.downloads);
    traffic.launches = std::max(traffic.launches, after.launches - before.launches);
  }
  EXPECT_EQ(sim.steps(), 3 + 3 * kFrameSubsteps);
  return traffic;
}

// Substep by substep (ReducedOptions::frame_graphs off); frames run as graphs are the next test's.
TEST(ReducedSim, FramesReuseTheirBuffersAndReadBackOnce) {
  // Up: nothing (the samples of many substeps go up at once, every point's once; x̂ and v̂ stay on the
  // device). Down, once a frame: each substep's row of failure slots with the domain checks' (samples,
  // quadrature) and the records of the points they name, the samples' largest speed and the new
  // [x̂ | v̂ | status] (the projection is solved on the device). The grid of the few samples' stencils keeps
  // its block count on the device.
  constexpr std::int64_t per_frame = 1;
  const FrameTraffic every = frame_traffic(engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Never);
  EXPECT_EQ(every.allocating_frames, 0);
  EXPECT_EQ(every.largest_uploads, 0);
  EXPECT_EQ(every.largest_downloads, per_frame);
  // Launches: a few microseconds of the host's each on CUDA outside a graph, the bulk of a small substep's
  // time there (bench/results/gpu-notes.md). Per substep: the substep's inputs (3), the samples' gather, the
  // kinematics, the grid's build (4), P2G, the grid update, G2P and the projection with its read-back row
  // (4); the bounds are today's counts, so that a change that adds launches says so here.
  EXPECT_LE(every.launches, 20 * kFrameSubsteps);

  // The neighbours' and the Eulerian points' counts vary with the samples: their buffers grow with
  // headroom now and then (not in these frames), where they were allocated every substep.
  const FrameTraffic neighbours = frame_traffic(engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Always);
  // The nodes near the samples are found, and the neighbours compacted and counted, on the device; the launches
  // after the compaction run over every material point's slot and stop at the count, so nothing is sized by it.
  EXPECT_EQ(neighbours.allocating_frames, 0);
  EXPECT_EQ(neighbours.largest_uploads, 0);
  EXPECT_EQ(neighbours.largest_downloads, per_frame);
  EXPECT_LE(neighbours.launches, 27 * kFrameSubsteps);  // one more than when counted on the host: their total

  const FrameTraffic eulerian = frame_traffic(engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Auto);
  EXPECT_LE(eulerian.allocating_frames, 2);
  // As every point's (its domain check covers the samples alone): the cells around the samples, the points
  // kept in them and the points used are counted on the device, and the launches that read those counts run
  // over bounds (for few samples, every cell they could find).
  EXPECT_EQ(eulerian.largest_uploads, 0);
  EXPECT_EQ(eulerian.largest_downloads, per_frame);
  // The Eulerian kinematics launch 19: the samples' decoding and domain check, the cells near them (8),
  // the points placed, warm-started, inverted, tallied (2), kept, selected and gathered.
  EXPECT_LE(eulerian.launches, 33 * kFrameSubsteps);

  // Gauss–Newton runs where the samples are (rom::project_positions): the position–velocity projection
  // costs the host what the velocity projection does, whatever its iterations.
  const FrameTraffic position = frame_traffic(engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Auto,
                                              engine::RomProjection::PositionVelocity);
  EXPECT_LE(position.allocating_frames, 2);
  EXPECT_EQ(position.largest_uploads, 0);
  EXPECT_EQ(position.largest_downloads, per_frame);
  // Gauss–Newton is one launch (CUDA's one block, and the CPU's stand-in for it): one more than the velocity
  // projection's.
  EXPECT_LE(position.launches, 34 * kFrameSubsteps);
}

// A frame replayed as a graph costs the host a launch, the copy of its samples to where the graph reads them,
// the frame's start time (one upload: the substeps' times are computed on the device from it) and the
// read-back. Gauss–Newton is one block on the CPU as on CUDA.
TEST(ReducedSim, AFrameRunAsAGraphCostsTheHostALaunch) {
  struct Case {
    engine::RomQuadrature quadrature;
    engine::NeighbourSearch search;
    engine::RomProjection projection;
  };
  for (const Case c :
       {Case{engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Never, engine::RomProjection::Velocity},
        Case{engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Always, engine::RomProjection::Velocity},
        Case{engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Never, engine::RomProjection::Velocity},
        Case{engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Never,
             engine::RomProjection::PositionVelocity}}) {
    const FrameTraffic graphs = frame_traffic(c.quadrature, c.search, c.projection, true);
    EXPECT_LE(graphs.allocating_frames, 1);  // the first frame's staged samples
    EXPECT_EQ(graphs.largest_uploads, 1);
    EXPECT_EQ(graphs.largest_downloads, 1);
    EXPECT_EQ(graphs.launches, 2);
  }
  EXPECT_FALSE(deformed_body(engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Auto,
                             engine::RomProjection::Velocity, false)
                   .runs_frame_graphs());
}

// A cube under a floor that rises into it at 2 m/s until t = 15.5 ms: frames of 6 substeps of 1 ms replayed
// as graphs give the state that the same frames give substep by substep, bit for bit on one CPU thread (each
// launch's arguments as at capture, its inputs from device memory: a time baked in would hold the floor
// still). The frame the floor leaves in runs substep by substep, the one after it is captured anew, and so is
// a frame of another Δt; a frame of the Δt before finds its graph kept.
// Searching the Lagrangian neighbours, 2 samples, whose neighbours are a part of the cube, their count changing
// as the cube moves.
engine::ReducedSim pushed_cube(engine::RomQuadrature quadrature, engine::RomProjection projection, bool frame_graphs,
                               engine::NeighbourSearch search = engine::NeighbourSearch::Never) {
  engine::FullOrderConfig config = falling_config();
  engine::ColliderSpec floor;
  floor.initial.shape = mpm::ColliderShape::HalfSpace;
  floor.initial.center = Vec3<float>(0.5f, 0.37f, 0.5f);
  floor.initial.linear_velocity = Vec3<float>(0.0f, 2.0f, 0.0f);
  floor.end = 0.0155;
  config.colliders.push_back(floor);
  engine::ReducedOptions options;
  options.quadrature = quadrature;
  options.projection = projection;
  options.neighbour_search = search;
  options.samples = search == engine::NeighbourSearch::Always ? 2 : 10;
  options.seed = 3;
  options.frame_graphs = frame_graphs ? engine::GraphReplay::Always : engine::GraphReplay::Never;
  return engine::ReducedSim(test::exec_with_threads(1), config,
                            quadrature == engine::RomQuadrature::Domains ? cube_with_domains() : cube(),
                            test::translation_map(), {0.0f, 0.0f, 0.0f}, options);
}

// Bit for bit on one CPU thread; on CUDA the grid's float atomics sum in any order, so to rounding there.
TEST(ReducedSim, FramesReplayedAsGraphsMatchFramesRunSubstepBySubstep) {
  struct Quadrature {
    engine::RomQuadrature quadrature;
    engine::NeighbourSearch search;
  };
  for (const Quadrature q : {Quadrature{engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Never},
                             Quadrature{engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Always},
                             Quadrature{engine::RomQuadrature::Eulerian, engine::NeighbourSearch::Never},
                             Quadrature{engine::RomQuadrature::Domains, engine::NeighbourSearch::Never}})
    for (const engine::RomProjection projection :
         {engine::RomProjection::Velocity, engine::RomProjection::PositionVelocity}) {
      SCOPED_TRACE(
          fmt::format("quadrature {}, search {}, projection {}", int(q.quadrature), int(q.search), int(projection)));
      engine::ReducedSim graphs = pushed_cube(q.quadrature, projection, true, q.search);
      engine::ReducedSim eager = pushed_cube(q.quadrature, projection, false, q.search);
      ASSERT_TRUE(graphs.runs_frame_graphs());
      ASSERT_EQ(graphs.searches_neighbours(), q.search == engine::NeighbourSearch::Always);
      for (int f = 0; f < 4; ++f) {
        graphs.substeps(kDt, 6);
        eager.substeps(kDt, 6);
      }
      // Frame 1 runs eagerly (it sizes the buffers), 2 is captured, 3 sees the floor leave, 4 is captured anew.
      EXPECT_EQ(graphs.graph_captures(), 2);
      EXPECT_EQ(graphs.graph_frames(), 2);
      test::expect_replay_matches(graphs.xhat(), eager.xhat());
      test::expect_replay_matches(graphs.vhat(), eager.vhat());
      EXPECT_GT(graphs.vhat()[1], 0.5f);  // the floor threw the cube up
      graphs.substeps(0.5f * kDt, 6);
      eager.substeps(0.5f * kDt, 6);
      EXPECT_EQ(graphs.graph_captures(), 3);
      graphs.substeps(kDt, 6);  // the graph of the Δt before was kept
      eager.substeps(kDt, 6);
      EXPECT_EQ(graphs.graph_captures(), 3);
      test::expect_replay_matches(graphs.xhat(), eager.xhat());
      test::expect_replay_matches(graphs.vhat(), eager.vhat());
      EXPECT_EQ(graphs.time(), eager.time());
      EXPECT_EQ(graphs.steps(), eager.steps());
      const auto launches = graphs.stage_launches();
      EXPECT_EQ(launches.back(), (std::pair<std::string, std::int64_t>("frame_graphs", 4)));
      if (graphs.searches_neighbours()) {
        // The neighbours' count, kept on the device, is a part of the cube and what the eager run found.
        EXPECT_LT(graphs.last_quadrature_count(), 4096);
        EXPECT_EQ(graphs.last_quadrature_count(), eager.last_quadrature_count());
        EXPECT_EQ(graphs.lagrangian_quadrature_points(), eager.lagrangian_quadrature_points());
      }
    }
}

// A frame read back once runs the substeps one read-back per substep would: the same state after it.
TEST(ReducedSim, AFrameReadBackOnceMatchesSubstepsReadBackEach) {
  for (const engine::RomQuadrature quadrature : {engine::RomQuadrature::Lagrangian, engine::RomQuadrature::Eulerian}) {
    engine::ReducedSim frame =
        deformed_body(quadrature, engine::NeighbourSearch::Auto, engine::RomProjection::Velocity);
    engine::ReducedSim each = deformed_body(quadrature, engine::NeighbourSearch::Auto, engine::RomProjection::Velocity);
    frame.substeps(kDt, 8);
    for (int s = 0; s < 8; ++s) each.substep(kDt);
    EXPECT_EQ(frame.steps(), 8);
    EXPECT_DOUBLE_EQ(frame.time(), each.time());
    // To rounding: the P2G sums' order varies with the threads (atomics).
    expect_same_xhat(frame.xhat(), each.xhat());
    EXPECT_LT(largest_difference(frame.vhat(), each.vhat()), 1e-5f);
    // The frame's step follows its largest speed, the last substep's here (the body falls faster).
    EXPECT_NEAR(frame.stable_dt(), each.stable_dt(), 1e-6f * each.stable_dt());
  }
  engine::ReducedSim sim =
      deformed_body(engine::RomQuadrature::Lagrangian, engine::NeighbourSearch::Never, engine::RomProjection::Velocity);
  EXPECT_THROW(sim.substeps(kDt, 0), Error);
  EXPECT_THROW(sim.substeps(kDt, engine::ReducedSim::kMostSubstepsPerReadback + 1), Error);
}

// advance_to lands on the frame's time in substeps of equal length under the stable step, read back once
// for the frame.
TEST(ReducedSim, AdvanceToReadsBackOncePerFrameInEqualSubsteps) {
  engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
  const double dt = sim.stable_dt(), end = 10.5 * dt;
  const memory::Traffic before = memory::traffic();
  ASSERT_TRUE(sim.advance_to(end));
  EXPECT_EQ(memory::traffic().downloads - before.downloads, 1);
  EXPECT_EQ(sim.steps(), 11);
  EXPECT_EQ(sim.time(), end);
  // A frame of more substeps than one read-back holds takes several.
  const std::int64_t steps = sim.steps();
  const double frame = (engine::ReducedSim::kMostSubstepsPerReadback + 2) * double(sim.stable_dt());
  const memory::Traffic later = memory::traffic();
  ASSERT_TRUE(sim.advance_to(end + frame));
  EXPECT_EQ(memory::traffic().downloads - later.downloads, 2);
  EXPECT_GE(sim.steps() - steps, engine::ReducedSim::kMostSubstepsPerReadback + 2);
  EXPECT_EQ(sim.time(), end + frame);
  // `stop` is asked before each read-back's substeps.
  int asked = 0;
  EXPECT_FALSE(sim.advance_to(sim.time() + 1.0, [&asked] { return ++asked == 2; }));
  EXPECT_EQ(asked, 2);
}

// Auto searches only where the samples reach under half the body: never with every point sampled, nor
// on a body a few stencils across.
TEST(ReducedSim, AutoSearchesNeighboursOnlyWhereTheyAreFewerThanThePoints) {
  mpm::ParticleInit large =
      test::lattice_box(Vec3<float>::constant(0.25f), Vec3<float>::constant(0.75f), kDx, 2, 1000.0f);
  auto searches = [&](const mpm::ParticleInit& body, Index samples) {
    engine::ReducedOptions options;
    options.samples = samples;
    return engine::ReducedSim(test::exec(), falling_config(), body, test::translation_map(), {0.0f, 0.0f, 0.0f},
                              options)
        .searches_neighbours();
  };
  EXPECT_TRUE(searches(large, 3));     // 3 × 125 cells × 8 points = 3,000 < 32,768 / 2
  EXPECT_FALSE(searches(large, 100));  // 100,000 points' reach: the body
  EXPECT_FALSE(searches(large, 0));    // every point is a sample
  EXPECT_FALSE(searches(cube(), 3));   // 3,000 of 4,096
}

TEST(ReducedSim, EulerianQuadratureReproducesTheFullOrderTranslation) {
  engine::ReducedOptions eulerian;
  eulerian.quadrature = engine::RomQuadrature::Eulerian;
  EXPECT_LT(largest_difference(full_order_positions(), reduced_positions(eulerian)), kTrajectoryTolerance);
  eulerian.samples = 10;
  eulerian.projection = engine::RomProjection::PositionVelocity;
  EXPECT_LT(largest_difference(full_order_positions(), reduced_positions(eulerian)), kTrajectoryTolerance);
}

// Warm starts (kernels/rom/eulerian_warm_start.h): a point whose place was inverted in the last substep starts
// from that solution. Under a map that deforms the body and moves with x̂, with every point sampled so that the
// places persist, they take fewer evaluations of g than starts from the cells' samples (measured: 9 % fewer),
// and they change the trajectory less than halving the inversion's tolerance does (measured after 40 substeps:
// 0.95 µm against 1.9 µm): both stop within the tolerance, at other points of it.
TEST(ReducedSim, WarmStartsSaveEvaluationsAndKeepTheTrajectoryWithinTheTolerance) {
  struct Run {
    std::vector<float> positions;
    double evaluations_per_point = 0.0;
    std::int64_t warm_starts = 0, unconverged = 0;
  };
  const auto run = [](bool warm_start, float tolerance) {
    engine::ReducedOptions options;
    options.quadrature = engine::RomQuadrature::Eulerian;
    options.warm_start_inversion = warm_start;
    options.inversion_tolerance = tolerance;
    engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::small_nonlinear_map(0.375f, 0.25f, 0.01f),
                           {0.0f, 0.0f, 0.0f}, options);
    for (int s = 0; s < 40; ++s) sim.substep(kDt);
    return Run{sim.decode_positions(), double(sim.eulerian_map_evaluations()) / double(sim.quadrature_points_used()),
               sim.eulerian_warm_starts(), sim.quadrature_points_unconverged()};
  };
  const Run cold = run(false, 1e-4f), warm = run(true, 1e-4f), half_tolerance = run(false, 5e-5f);
  EXPECT_EQ(cold.warm_starts, 0);
  EXPECT_GT(warm.warm_starts, 0);
  EXPECT_EQ(warm.unconverged, 0);
  EXPECT_LT(warm.evaluations_per_point, 0.95 * cold.evaluations_per_point);
  const float tolerance_spread = largest_difference(half_tolerance.positions, cold.positions);
  EXPECT_GT(tolerance_spread, 0.0f);  // the comparison is not of identical runs
  EXPECT_LE(largest_difference(warm.positions, cold.positions), tolerance_spread);
}

TEST(ReducedSim, EulerianQuadratureWeighsTheBodyAndDropsPointsOutsideIt) {
  // At x̂ = 0 the map is the identity, and ℓ = 2 points per cell of a lattice body sampled at 2 per
  // cell sit exactly on its material points: the quadrature mass is the body's mass.
  const mpm::ParticleInit body = cube();
  engine::ReducedOptions eulerian;
  eulerian.quadrature = engine::RomQuadrature::Eulerian;
  engine::ReducedSim sim(test::exec(), falling_config(), body, test::translation_map(), {0.0f, 0.0f, 0.0f}, eulerian);
  sim.substep(kDt);
  double mass = 0.0;
  for (const float m : body.mass) mass += m;
  EXPECT_NEAR(sim.last_quadrature_mass(), mass, 1e-5 * mass);
  EXPECT_EQ(sim.quadrature_points_used(), body.count());
  EXPECT_GT(sim.quadrature_points_outside(), 0);  // the cells around the body reach its boundary nodes
  EXPECT_EQ(sim.quadrature_points_unconverged(), 0);
}

// A sample at the body's surface reads nodes no Eulerian quadrature point reaches: here, per axis, the
// body spans cells 8 to 10.74 at 8 points per cell, so its outermost points (at 10.68) read node 12, in
// the grid block of nodes 12-15, while the quadrature points inside the body (at 8.25 ... 10.25; the
// one at 10.75 lies outside) reach nodes 7-11 only. Those nodes must exist and carry velocity 0: from
// rest, with no stress, each sample moves at g Δt times its weight on nodes 7-11.
TEST(ReducedSim, EulerianSamplesReadNodesNoQuadraturePointReaches) {
  const mpm::ParticleInit body =
      test::lattice_box(Vec3<float>::constant(8.0f * kDx), Vec3<float>::constant(10.75f * kDx), kDx, 8, 1000.0f);
  const float shift = -0.01f * kDx;  // x̂: off the lattice, so no quadrature point is on the body's faces
  engine::ReducedOptions eulerian;
  eulerian.quadrature = engine::RomQuadrature::Eulerian;
  engine::FullOrderConfig config = falling_config();
  // No stress at all: at F = I the elastic stress is 0 only to rounding, which moved v̂ by 5e-7 m/s.
  config.materials[0].strength_off_until = 1.0;
  engine::ReducedSim sim(test::exec(), config, body, test::translation_map(), {shift, shift, shift}, eulerian);
  sim.substep(kDt);
  const Index n = body.count();
  double weight_on_mass = 0.0;
  Index beyond = 0;  // samples whose stencils reach node 12
  for (Index p = 0; p < n; ++p) {
    const Vec3<float> x = test::plane_vector(body.x, n, p) + Vec3<float>::constant(shift);
    const mpm::QuadraticStencil<float> stencil(x, 1.0f / kDx);
    double product = 1.0;
    for (int a = 0; a < 3; ++a) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += stencil.base[a] + k <= 11 ? stencil.w[a][k] : 0.0;
      product *= sum;
      beyond += stencil.base[a] + 2 == 12 && stencil.w[a][2] > 0.01f;
    }
    weight_on_mass += product / double(n);
  }
  ASSERT_GT(beyond, 0);
  ASSERT_LT(weight_on_mass, 1.0 - 1e-3);  // the missing weight is measurable
  // Every point is a sample and g(X; x̂) = X + x̂: v̂ is the samples' mean velocity.
  EXPECT_EQ(sim.vhat()[0], 0.0f);
  EXPECT_NEAR(sim.vhat()[1], config.gravity[1] * kDt * weight_on_mass, 1e-6 * std::fabs(config.gravity[1] * kDt));
  EXPECT_EQ(sim.vhat()[2], 0.0f);
}

TEST(ReducedSim, DecodesAFinerSamplingOfTheBody) {
  // Super-resolution: the state at points the simulation never had, here a lattice twice as fine.
  engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
  for (int s = 0; s < 5; ++s) sim.substep(kDt);
  const mpm::ParticleInit fine =
      test::lattice_box(Vec3<float>::constant(0.375f), Vec3<float>::constant(0.625f), kDx, 4, 1000.0f);
  const engine::ReducedSim::DecodedState state = sim.decode(fine.x);
  const Index n = fine.count();
  ASSERT_EQ(Index(state.x.size()), 3 * n);
  for (Index p = 0; p < n; p += 97)
    for (int a = 0; a < 3; ++a) {
      EXPECT_FLOAT_EQ(state.x[a * n + p], fine.x[a * n + p] + sim.xhat()[a]);
      EXPECT_FLOAT_EQ(state.v[a * n + p], sim.vhat()[a]);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(state.F[(3 * a + c) * n + p], a == c ? 1.0f : 0.0f);
    }
}

TEST(ReducedSim, InitialGeneralizedVelocityFitsTheInitialVelocities) {
  const engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(sim.vhat()[j], kInitialVelocity[j], 1e-6f);
}

TEST(ReducedSim, NonFiniteGeneralizedCoordinatesStopWithAClearError) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  try {
    engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, nan, 0.0f}, {});
    FAIL() << "a non-finite x̂ must be an error";
  } catch (const engine::NonFiniteError& error) {
    EXPECT_NE(std::string(error.what()).find("x̂"), std::string::npos) << error.what();
  }
}

// A reduced state that decodes outside the grid (x̂ diverged) stops the run, naming the step, the
// first material point out and where g sends it, for samples and Lagrangian quadrature points alike.
TEST(ReducedSim, StateDecodedOutsideTheDomainStopsNamingThePoint) {
  const mpm::ParticleInit body = cube();
  for (const Index samples : {Index(0), Index(10)}) {
    // x̂ = (0.6, 0, 0) moves the cube's far face (x = 0.625) to 1.225 m, past the 1 m domain.
    engine::ReducedOptions options;
    options.samples = samples;
    engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.6f, 0.0f, 0.0f},
                           options);
    try {
      sim.substep(kDt);
      FAIL() << "a state outside the domain must be an error";
    } catch (const engine::NonFiniteError& error) {
      const std::string message = error.what();
      EXPECT_EQ(error.step(), 0);
      EXPECT_GE(error.index(), 0);
      EXPECT_NE(message.find("material point " + std::to_string(error.index())), std::string::npos) << message;
      EXPECT_NE(message.find("outside the domain"), std::string::npos) << message;
      // The translation map moves the point by x̂: its decoded place, not the one the step kept it at.
      const Index n = body.count(), p = error.index();
      const std::string place =
          fmt::format("decodes to ({:.4g}, {:.4g}, {:.4g}) m", body.x[p] + 0.6f, body.x[n + p], body.x[2 * n + p]);
      EXPECT_NE(message.find(place), std::string::npos) << message;
    }
  }
}

// A failure in the middle of a frame read back once stops as a read-back after each substep would: the
// same substep, stage, point and message, and the state of the substep before it.
TEST(ReducedSim, AFailureInAFrameNamesItsSubstepAsReadingBackEachWould) {
  mpm::ParticleInit body = cube();
  for (Index p = 0; p < body.count(); ++p) test::set_plane_vector(body.v, body.count(), p, Vec3<float>(8.0f, 0, 0));
  struct Case {
    engine::RomQuadrature quadrature;
    Index samples;
  };
  for (const Case c : {Case{engine::RomQuadrature::Lagrangian, 0}, Case{engine::RomQuadrature::Lagrangian, 10},
                       Case{engine::RomQuadrature::Eulerian, 10}}) {
    engine::ReducedOptions options;
    options.quadrature = c.quadrature;
    options.samples = c.samples;
    // x̂ = (0.25, 0, 0) puts the cube's far face at 0.875 m; at 8 m/s it leaves the domain's interior after a
    // few substeps.
    auto run = [&](bool frame) {
      engine::ReducedSim sim(test::exec(), falling_config(), body, test::translation_map(), {0.25f, 0.0f, 0.0f},
                             options);
      try {
        if (frame)
          sim.substeps(kDt, 20);
        else
          for (int s = 0; s < 20; ++s) sim.substep(kDt);
      } catch (const engine::NonFiniteError& error) {
        return std::tuple(std::string(error.what()), error.step(), error.index(), sim.steps(), sim.time(), sim.xhat());
      }
      ADD_FAILURE() << "leaving the domain must stop the run";
      return std::tuple(std::string(), std::int64_t(-1), std::int64_t(-1), std::int64_t(-1), 0.0, std::vector<float>());
    };
    const auto each = run(false), frame = run(true);
    const auto& [message, step, point, steps, time, xhat] = frame;
    // The P2G sums' order varies with the threads (atomics): x̂ to rounding, the rest exactly.
    const std::string& each_message = std::get<0>(each);
    EXPECT_EQ(message.substr(0, message.find("x̂ =")), each_message.substr(0, each_message.find("x̂ ="))) << message;
    EXPECT_EQ(step, std::get<1>(each));
    EXPECT_EQ(point, std::get<2>(each));
    EXPECT_EQ(steps, std::get<3>(each));
    EXPECT_EQ(time, std::get<4>(each));
    EXPECT_LT(largest_difference(xhat, std::get<5>(each)), 1e-6f);
    EXPECT_GT(step, 0) << message;  // in the middle of the frame
    EXPECT_EQ(steps, step);
    EXPECT_NE(message.find(fmt::format("material point {} decodes to", point)), std::string::npos) << message;
  }
}

// A stress that is not finite stops P2G naming a material point for the Lagrangian quadrature, and for
// the Eulerian one, whose points are none, the point's place.
TEST(ReducedSim, NonFiniteStressNamesTheQuadraturePoint) {
  engine::FullOrderConfig config = falling_config();
  config.materials[0].params.mu = std::numeric_limits<float>::quiet_NaN();
  for (const engine::RomQuadrature quadrature : {engine::RomQuadrature::Lagrangian, engine::RomQuadrature::Eulerian}) {
    engine::ReducedOptions options;
    options.quadrature = quadrature;
    engine::ReducedSim sim(test::exec(), config, cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, options);
    try {
      sim.substep(kDt);
      FAIL() << "a non-finite stress must stop the run";
    } catch (const engine::NonFiniteError& error) {
      const std::string message = error.what();
      EXPECT_EQ(error.stage(), mpm::Stage::P2G);
      if (quadrature == engine::RomQuadrature::Lagrangian) {
        EXPECT_EQ(error.index(), 0);
        EXPECT_NE(message.find("material point 0 (a quadrature point)"), std::string::npos) << message;
      } else {
        EXPECT_EQ(error.index(), -1);
        EXPECT_NE(message.find("the Eulerian quadrature point at x = (0.3"), std::string::npos) << message;
      }
    }
  }
}

// ReducedOptions::cfl replaces the scene's CFL number in the reduced substep (romp run --rom-cfl), within
// (0, 1].
TEST(ReducedSim, CflOptionScalesTheStableStep) {
  auto stable_dt = [](double cfl) {
    engine::ReducedOptions options;
    options.cfl = cfl;
    return engine::ReducedSim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f},
                              options)
        .stable_dt();
  };
  EXPECT_EQ(stable_dt(0.0), stable_dt(falling_config().cfl));  // 0: the scene's
  // Under max_dt (1 ms) the step is proportional to the CFL number.
  EXPECT_LT(stable_dt(0.2), 1e-3f);
  EXPECT_NEAR(stable_dt(0.1), 0.5f * stable_dt(0.2), 1e-6f * stable_dt(0.2));
  EXPECT_THROW(stable_dt(1.5), Error);
  EXPECT_THROW(stable_dt(-0.1), Error);
}

// After a substep the CFL step uses the samples' largest speed, read back with the failure slots: under
// the translation every sample moves at v̂, so cfl Δx (1/Δt − 1/Δt_rest) = |v̂|, Δt_rest being the step
// of the same body at rest (the wave speed alone).
TEST(ReducedSim, TheNextStepUsesTheSamplesLargestSpeed) {
  engine::ReducedOptions options;
  options.cfl = 0.2;  // under max_dt
  mpm::ParticleInit at_rest = cube();
  std::fill(at_rest.v.begin(), at_rest.v.end(), 0.0f);
  const float rest_dt =
      engine::ReducedSim(test::exec(), falling_config(), at_rest, test::translation_map(), {0.0f, 0.0f, 0.0f}, options)
          .stable_dt();
  engine::ReducedSim sim(test::exec(), falling_config(), cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, options);
  sim.substep(kDt);
  const std::vector<float>& vhat = sim.vhat();
  const double speed = std::sqrt(double(vhat[0]) * vhat[0] + double(vhat[1]) * vhat[1] + double(vhat[2]) * vhat[2]);
  const double implied = 0.2 * double(kDx) * (1.0 / double(sim.stable_dt()) - 1.0 / double(rest_dt));
  EXPECT_NEAR(implied, speed, 1e-3 * speed);
}

// Substeps read back one by one run at the CFL number asked for; a frame's substeps follow the speeds of the
// read-back before, so a body falling faster within the frame runs a little over it, which
// largest_cfl_number shows.
TEST(ReducedSim, TheLargestCflNumberShowsTheFramesLag) {
  engine::ReducedOptions options;
  options.cfl = 0.2;  // under max_dt
  mpm::ParticleInit at_rest = cube();
  std::fill(at_rest.v.begin(), at_rest.v.end(), 0.0f);
  engine::ReducedSim sim(test::exec(), falling_config(), at_rest, test::translation_map(), {0.0f, 0.0f, 0.0f}, options);
  for (int s = 0; s < 5; ++s) sim.substep(sim.stable_dt());
  EXPECT_NEAR(sim.largest_cfl_number(), 0.2, 1e-6);
  ASSERT_TRUE(sim.advance_to(sim.time() + 0.05));
  EXPECT_GT(sim.largest_cfl_number(), 0.2 + 1e-6);
  EXPECT_LT(sim.largest_cfl_number(), 0.25);
}

// A PIC scene (pic-flip with flip_alpha = 0, the paper's full-order model) runs the same reduced step
// as an APIC one, which the full-order PIC run of the translating cube matches too; FLIP is refused.
TEST(ReducedSim, PicScenesRunTheSameStepAndFlipIsRefused) {
  engine::FullOrderConfig pic = falling_config();
  pic.transfer = mpm::Transfer::PicFlip;
  pic.flip_alpha = 0.0f;
  engine::ReducedSim sim(test::exec(), pic, cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
  engine::FullOrderSim full(test::exec(), pic, cube());
  for (int s = 0; s < kSteps; ++s) {
    sim.substep(kDt);
    full.substep(kDt);
  }
  EXPECT_LE(largest_difference(sim.decode_positions(), reduced_positions({})), 1e-6f);
  EXPECT_LT(largest_difference(full.particles().positions_in_initial_order(full.exec()), sim.decode_positions()),
            kTrajectoryTolerance);
  pic.flip_alpha = 0.5f;
  try {
    engine::ReducedSim(test::exec(), pic, cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
    FAIL() << "a reduced simulation accepted FLIP";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("solver.flip_alpha = 0.5"), std::string::npos) << error.what();
  }
}

TEST(ReducedSim, PlasticMaterialsAreRejected) {
  engine::FullOrderConfig config = falling_config();
  config.materials = {scene::nclaw_material(scene::NclawMaterial::Sand)};
  EXPECT_THROW(engine::ReducedSim(test::exec(), config, cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {}),
               Error);
}

TEST(ReducedSim, TheImplicitIntegratorIsRefusedByName) {
  engine::FullOrderConfig config = falling_config();
  config.integrator = engine::Integrator::Implicit;
  try {
    engine::ReducedSim(test::exec(), config, cube(), test::translation_map(), {0.0f, 0.0f, 0.0f}, {});
    FAIL() << "a reduced simulation accepted the implicit integrator";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("solver.integrator"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace romp
