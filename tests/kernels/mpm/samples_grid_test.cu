// The grid of a reduced substep: built from a few samples without reading its block count back, P2G from
// other points adding only into its blocks, and the node kernels skipping storage the device did not hand
// out. The samples' nodes must come out as on a grid built from every point. And a full-order substep of few
// particles, whose sort leaves its count of runs on the device as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#include "kernels/material/material.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/stencil_nodes.h"
#include "kernels/mpm/step.h"
#include "tests/support/random_planes.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

constexpr float kDx = 1.0f / 32.0f;
constexpr int kCells = 32;

// Every third point of `x` (three planes of n): the "samples" the grid is built from.
std::vector<float> every_third(const std::vector<float>& x, Index n) {
  std::vector<float> picked;
  for (int a = 0; a < 3; ++a)
    for (Index p = 0; p < n; p += 3) picked.push_back(x[a * n + p]);
  return picked;
}

// Moving, stressed particles of one elastic material.
ParticleInit moving_particles(std::vector<float> x) {
  const Index n = Index(x.size() / 3);
  ParticleInit init;
  init.x = std::move(x);
  init.v = test::random_planes(n, -1.0f, 1.0f, 3);
  init.F = std::vector<float>(9 * n);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> stretch(-0.1f, 0.1f);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (Index p = 0; p < n; ++p) init.F[(3 * r + c) * n + p] = (r == c ? 1.0f : 0.0f) + stretch(rng);
  init.mass.assign(n, 1e-3f);
  init.volume0.assign(n, 1e-6f);
  init.material.assign(n, 0);
  init.dirichlet_group.assign(n, kNoDirichletGroup);
  return init;
}

// A substep's parameters: one neo-Hookean material, walls 2 cells thick, gravity.
struct Step {
  DeviceBuffer<material::MaterialParams<float>> materials;
  DeviceBuffer<std::int64_t> failures;
  StepParams params;

  Step() {
    const Exec& exec = test::exec();
    materials = DeviceBuffer<material::MaterialParams<float>>::from_host(
        exec.backend, {material::MaterialParams<float>::neo_hookean(material::lame_from_young_poisson(1e5f, 0.3f))});
    failures = DeviceBuffer<std::int64_t>::from_host(exec.backend, std::vector<std::int64_t>(kStageCount, kNoFailure));
    params.dt = 1e-4f;
    params.transfer = Transfer::Apic;
    for (int a = 0; a < 3; ++a) params.domain.cells[a] = kCells;
    params.domain.wall_cells = 2;
    params.materials = materials.span();
    params.first_failure = failures.span();
  }
};

// Mass and velocity of each sample's 27 stencil nodes after the grid update (27 per sample, in stencil order).
struct ReadStencilNodes {
  Vec3Planes<const float> samples;
  GridView grid;
  Span<float> out;  // 4 values per node: mass, velocity
  ROMP_HD void operator()(Index s) const {
    const QuadraticStencil<float> stencil(samples.load(s), grid.inverse_dx);
    const StencilNodes nodes(stencil, grid.table);
    for_each_stencil_offset([&](int i, int j, int k) {
      const Index n = nodes.node(i, j, k);
      const Index slot = 4 * (27 * s + 9 * i + 3 * j + k);
      out[slot] = grid.mass[n];
      const Vec3<float> v = grid.velocity.load(n);
      for (int a = 0; a < 3; ++a) out[slot + 1 + a] = v[a];
    });
  }
};

std::vector<float> samples_nodes(const GridView& grid, const DeviceBuffer<float>& samples, Index m) {
  DeviceBuffer<float> out(test::exec().backend, 4 * 27 * m);
  for_each(test::exec(), m, ReadStencilNodes{Vec3Planes<const float>(samples.data(), m), grid, out.span()});
  return out.to_host();
}

TEST(SparseGrid, FewPointsGridHoldsTheirBlocksWithoutReadingItsCountBack) {
  const Exec& exec = test::exec();
  const Index n = 300;
  const std::vector<float> x = test::random_planes(n, 3 * kDx, 1.0f - 3 * kDx, 8);
  const DeviceBuffer<float> positions = DeviceBuffer<float>::from_host(exec.backend, x);
  SparseGrid counted(exec.backend, kDx, false), few(exec.backend, kDx, false);
  counted.rebuild(exec, Vec3Planes<const float>(positions.data(), n));
  few.rebuild_for_few_points(exec, Vec3Planes<const float>(positions.data(), n));  // sized here
  const memory::Traffic before = memory::traffic();
  few.rebuild_for_few_points(exec, Vec3Planes<const float>(positions.data(), n));
  const memory::Traffic after = memory::traffic();
  EXPECT_EQ(after.downloads, before.downloads);
  EXPECT_EQ(after.allocations, before.allocations);
  // The node kernels' bound covers the blocks; the device's count is exactly the counted rebuild's.
  EXPECT_GE(few.active_blocks(), counted.active_blocks());
  const std::vector<std::int64_t> counters = download(exec.backend, few.view().table.counters, exec.stream);
  EXPECT_EQ(counters[0], counted.active_blocks());
  EXPECT_EQ(counters[1], 0);
  EXPECT_EQ(counters[2], counted.active_nodes());

  const DeviceBuffer<float> too_many(exec.backend, 3 * (SparseGrid::kFewPoints + 1));
  EXPECT_THROW(few.rebuild_for_few_points(exec, Vec3Planes<const float>(too_many.data(), SparseGrid::kFewPoints + 1)),
               Error);
}

// P2G from every particle into the grid of a third of them (active nodes only), then the grid update, gives
// those particles' stencil nodes what the grid of every particle gives them. Before it, the few-points grid
// served more points and its storage beyond the blocks now handed out holds NaN: the node kernels must not
// touch it (a NaN velocity there would be reported as the grid update's failure).
TEST(ParticleToGridActiveNodes, GivesTheSamplesNodesWhatTheFullGridGives) {
  const Exec& exec = test::exec();
  const Index n = 900;
  const std::vector<float> x = test::random_planes(n, 0.3f, 0.6f, 9);
  ParticleSet particles(exec.backend, moving_particles(x));
  const std::vector<float> picked = every_third(x, n);
  const Index m = Index(picked.size() / 3);
  const DeviceBuffer<float> samples = DeviceBuffer<float>::from_host(exec.backend, picked);

  Step full_step;
  SparseGrid full(exec.backend, kDx, false);
  full.rebuild(exec, Vec3Planes<const float>(particles.view().x));
  particle_to_grid(exec, particles.view(), full.view(), full_step.params);
  update_grid(exec, full.view(), full_step.params);

  Step few_step;
  SparseGrid few(exec.backend, kDx, false);
  const DeviceBuffer<float> spread =
      DeviceBuffer<float>::from_host(exec.backend, test::random_planes(m, 0.1f, 0.9f, 10));
  few.rebuild_for_few_points(exec, Vec3Planes<const float>(spread.data(), m));
  const GridView stale = few.view();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> nans(std::size_t(stale.mass.size()), nan);
  upload(exec.backend, stale.mass, Span<const float>(nans.data(), stale.mass.size()), exec.stream);
  few.rebuild_for_few_points(exec, Vec3Planes<const float>(samples.data(), m));
  particle_to_grid_active_nodes(exec, particles.view(), few.view(), few_step.params);
  update_grid(exec, few.view(), few_step.params);

  EXPECT_EQ(few_step.failures.to_host(), std::vector<std::int64_t>(kStageCount, kNoFailure));
  const std::vector<float> expected = samples_nodes(full.view(), samples, m);
  const std::vector<float> got = samples_nodes(few.view(), samples, m);
  ASSERT_EQ(got.size(), expected.size());
  float largest = 0.0f;
  for (const float value : expected) largest = std::max(largest, std::fabs(value));
  ASSERT_GT(largest, 0.0f);
  // The same shares added in another order (atomics): rounding only.
  for (std::size_t i = 0; i < got.size(); ++i) ASSERT_NEAR(got[i], expected[i], 1e-5f * largest) << "value " << i;
}

// A full-order substep with few particles leaves its counts on the device (FullOrderSim::counts_on_device): the
// sort keeps its count of runs there and hands out the particle count of runs, those past its count empty, and
// the grid is the few-points one. The tiled P2G and the grid update over them give every particle's stencil
// nodes what the counts read back give, with no download.
TEST(ParticleToGridTiled, RunsCountedOnTheDeviceGiveWhatRunsReadBackGive) {
  const Exec& exec = test::exec();
  const Index n = 700;
  const std::vector<float> x = test::random_planes(n, 0.2f, 0.7f, 31);
  std::vector<std::vector<std::int32_t>> starts;
  std::vector<std::vector<float>> nodes;
  for (const ParticleSet::RunCount count : {ParticleSet::RunCount::ReadBack, ParticleSet::RunCount::OnDevice}) {
    const bool on_device = count == ParticleSet::RunCount::OnDevice;
    ParticleSet particles(exec.backend, moving_particles(x));
    SparseGrid grid(exec.backend, kDx, false);
    Step step;
    auto transfer = [&] {
      particles.sort_by_block(exec, 1.0f / kDx, count);
      const Vec3Planes<const float> positions(particles.view().x);
      if (on_device)
        grid.rebuild_for_few_points(exec, positions);
      else
        grid.rebuild(exec, positions);
      particle_to_grid_tiled(exec, particles.view(), grid.view(), step.params, particles.block_starts(),
                             particles.sorted_block_keys(), true);
      update_grid(exec, grid.view(), step.params);
    };
    transfer();  // sizes the buffers
    const memory::Traffic before = memory::traffic();
    transfer();
    const memory::Traffic after = memory::traffic();
    EXPECT_EQ(after.downloads - before.downloads, on_device ? 0 : 2) << "the sort's count and the grid's";
    EXPECT_EQ(after.allocations, before.allocations);
    starts.push_back(download(exec.backend, particles.block_starts(), exec.stream));
    DeviceBuffer<float> sorted_x(exec.backend, 3 * n);
    memory::copy(sorted_x.data(), exec.backend, particles.view().x.data(), exec.backend, 3 * n * sizeof(float),
                 exec.stream);
    nodes.push_back(samples_nodes(grid.view(), sorted_x, n));
    EXPECT_EQ(step.failures.to_host(), std::vector<std::int64_t>(kStageCount, kNoFailure));
  }
  // The runs read back, then empty runs up to the particle count.
  const std::size_t runs = starts[0].size() - 1;
  ASSERT_GT(runs, 10u);
  ASSERT_EQ(starts[1].size(), std::size_t(n + 1));
  for (std::size_t r = 0; r <= std::size_t(n); ++r)
    ASSERT_EQ(starts[1][r], r <= runs ? starts[0][r] : std::int32_t(n)) << "run " << r;
  // The same shares added in another order where the CPU's tiles flush from several threads: rounding only.
  float largest = 0.0f;
  for (const float value : nodes[0]) largest = std::max(largest, std::fabs(value));
  ASSERT_GT(largest, 0.0f);
  for (std::size_t i = 0; i < nodes[0].size(); ++i) ASSERT_NEAR(nodes[1][i], nodes[0][i], 1e-5f * largest) << i;
}

}  // namespace
}  // namespace romp::mpm
