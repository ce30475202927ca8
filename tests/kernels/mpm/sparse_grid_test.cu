// SparseGrid activates exactly the blocks the particle stencils touch, grows on demand, and
// ParticleSet's block sort is a permutation that can be undone.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "tests/support/random_planes.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

constexpr float kDx = 1.0f / 64.0f;

std::set<std::uint64_t> expected_blocks(const std::vector<float>& x, Index n) {
  std::set<std::uint64_t> blocks;
  for (Index p = 0; p < n; ++p) {
    const QuadraticStencil<float> s(Vec3<float>(x[p], x[n + p], x[2 * n + p]), 1.0f / kDx);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          blocks.insert(
              block_key((s.base[0] + i) / kBlockSide, (s.base[1] + j) / kBlockSide, (s.base[2] + k) / kBlockSide));
  }
  return blocks;
}

// Unit-mass, unit-volume particles of material 0 at positions x with velocities v (three planes each).
ParticleInit unit_particles(std::vector<float> x, std::vector<float> v) {
  const Index n = Index(x.size() / 3);
  ParticleInit init;
  init.x = std::move(x);
  init.v = std::move(v);
  init.mass.assign(n, 1.0f);
  init.volume0.assign(n, 1.0f);
  init.material.assign(n, 0);
  init.dirichlet_group.assign(n, kNoDirichletGroup);
  return init;
}

struct FindEachBlock {
  BlockTableView table;
  Span<const std::uint64_t> keys;
  Span<std::int32_t> found;
  ROMP_HD void operator()(Index b) const { found[b] = table.find(keys[b]); }
};

TEST(SparseGrid, ActivatesExactlyTheBlocksOfTheStencilsAndGrows) {
  const Exec& exec = test::exec();
  // Spread over the whole unit cube: thousands of blocks, far more than the initial provision.
  const Index n = 20000;
  const std::vector<float> x = test::random_planes(n, 2 * kDx, 1.0f - 2 * kDx, 7);
  const DeviceBuffer<float> positions = DeviceBuffer<float>::from_host(exec.backend, x, exec.stream);
  SparseGrid grid(exec.backend, kDx, false);
  grid.rebuild(exec, Vec3Planes<const float>(positions.data(), n));

  const std::set<std::uint64_t> expected = expected_blocks(x, n);
  ASSERT_EQ(grid.active_blocks(), Index(expected.size()));
  GridView view = grid.view();
  const std::vector<std::uint64_t> keys(expected.begin(), expected.end());
  const DeviceBuffer<std::uint64_t> key_buffer =
      DeviceBuffer<std::uint64_t>::from_host(exec.backend, keys, exec.stream);
  DeviceBuffer<std::int32_t> found(exec.backend, Index(keys.size()));
  for_each(exec, Index(keys.size()), FindEachBlock{view.table, key_buffer.span(), found.span()});
  std::vector<std::int32_t> indices = found.to_host(exec.stream);
  std::sort(indices.begin(), indices.end());
  for (std::size_t b = 0; b < indices.size(); ++b)
    ASSERT_EQ(indices[b], std::int32_t(b)) << "block indices are 0..blocks-1";
}

TEST(SparseGrid, InactiveBlockIsNotFound) {
  const Exec& exec = test::exec();
  const std::vector<float> x{0.5f, 0.5f, 0.5f};
  const DeviceBuffer<float> positions = DeviceBuffer<float>::from_host(exec.backend, x, exec.stream);
  SparseGrid grid(exec.backend, kDx, false);
  grid.rebuild(exec, Vec3Planes<const float>(positions.data(), 1));
  const std::vector<std::uint64_t> far{block_key(1, 1, 1)};
  const DeviceBuffer<std::uint64_t> keys = DeviceBuffer<std::uint64_t>::from_host(exec.backend, far, exec.stream);
  DeviceBuffer<std::int32_t> found(exec.backend, 1);
  for_each(exec, 1, FindEachBlock{grid.view().table, keys.span(), found.span()});
  EXPECT_EQ(found.to_host(exec.stream)[0], -1);
}

TEST(SparseGrid, MemoryFollowsTheOccupiedBlocksDownAgain) {
  const Exec& exec = test::exec();
  const Index n = 20000;
  const std::vector<float> spread = test::random_planes(n, 2 * kDx, 1.0f - 2 * kDx, 5);
  const std::vector<float> clustered(3 * n, 0.5f);
  const DeviceBuffer<float> wide = DeviceBuffer<float>::from_host(exec.backend, spread, exec.stream);
  const DeviceBuffer<float> narrow = DeviceBuffer<float>::from_host(exec.backend, clustered, exec.stream);
  SparseGrid grid(exec.backend, kDx, false);
  grid.rebuild(exec, Vec3Planes<const float>(wide.data(), n));
  const std::size_t grown = grid.bytes();
  grid.rebuild(exec, Vec3Planes<const float>(narrow.data(), n));
  grid.rebuild(exec, Vec3Planes<const float>(narrow.data(), n));
  EXPECT_LE(grid.active_blocks(), 8);
  EXPECT_LT(grid.bytes() * 10, grown) << "storage stayed sized for the spread-out particles";
}

// A stencil based at base covers nodes base..base+2 on each axis: inside block b's 27-block neighbourhood while
// base - 4 b is in [-4, 5] (and base >= 0).
TEST(SparseGrid, StencilWithinBlocksAroundAllowsFourNodesDownAndTwoUp) {
  const std::uint64_t key = block_key(5, 5, 5);
  const auto within = [key](int x, int y, int z) {
    const int base[3] = {x, y, z};
    return stencil_within_blocks_around(base, key);
  };
  for (int offset = -4; offset <= 5; ++offset) {
    EXPECT_TRUE(within(20 + offset, 20, 20)) << offset;
    EXPECT_TRUE(within(20, 20 + offset, 20)) << offset;
    EXPECT_TRUE(within(20, 20, 20 + offset)) << offset;
  }
  for (const int offset : {-5, 6}) {
    EXPECT_FALSE(within(20 + offset, 20, 20)) << offset;
    EXPECT_FALSE(within(20, 20 + offset, 20)) << offset;
    EXPECT_FALSE(within(20, 20, 20 + offset)) << offset;
  }
  EXPECT_TRUE(stencil_within_blocks_around(std::array<int, 3>{0, 0, 0}.data(), block_key(0, 0, 0)));
  EXPECT_FALSE(stencil_within_blocks_around(std::array<int, 3>{-1, 0, 0}.data(), block_key(0, 0, 0)));
}

// A grid built around the sorted particles' blocks holds every stencil the particles can reach while they stay
// within the allowance: random drifts up to 4 nodes down and 2 up from the position they were sorted at.
TEST(SparseGrid, GridAroundSortedBlocksHoldsTheStencilsOfParticlesThatDrifted) {
  const Exec& exec = test::exec();
  const Index n = 4000;
  ParticleSet particles(exec.backend,
                        unit_particles(test::random_planes(n, 8 * kDx, 0.5f, 21), std::vector<float>(3 * n)));
  particles.sort_by_block(exec, 1.0f / kDx);
  SparseGrid grid(exec.backend, kDx, false);
  grid.rebuild_around_blocks(exec, particles.block_starts(), particles.sorted_block_keys());
  EXPECT_LE(grid.active_blocks(), 27 * (particles.block_starts().size() - 1));

  // Sorted positions, each moved by up to [-4, 2] nodes minus a margin on every axis, with its sort key.
  std::vector<float> x(3 * n);
  memory::copy(x.data(), Backend::Cpu, particles.view().x.data(), exec.backend, x.size() * sizeof(float), exec.stream);
  std::vector<std::uint64_t> sorted_keys(n);
  memory::copy(sorted_keys.data(), Backend::Cpu, particles.sorted_block_keys().data(), exec.backend,
               n * sizeof(std::uint64_t), exec.stream);
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> drift(-3.99f * kDx, 1.99f * kDx);
  for (float& value : x) value += drift(rng);
  for (Index p = 0; p < n; ++p) {
    const QuadraticStencil<float> s(Vec3<float>(x[p], x[n + p], x[2 * n + p]), 1.0f / kDx);
    ASSERT_TRUE(stencil_within_blocks_around(s.base, sorted_keys[p])) << "particle " << p;
  }
  const std::set<std::uint64_t> needed = expected_blocks(x, n);
  const std::vector<std::uint64_t> keys(needed.begin(), needed.end());
  const DeviceBuffer<std::uint64_t> key_buffer =
      DeviceBuffer<std::uint64_t>::from_host(exec.backend, keys, exec.stream);
  DeviceBuffer<std::int32_t> found(exec.backend, Index(keys.size()));
  for_each(exec, Index(keys.size()), FindEachBlock{grid.view().table, key_buffer.span(), found.span()});
  const std::vector<std::int32_t> indices = found.to_host(exec.stream);
  for (std::size_t b = 0; b < keys.size(); ++b) ASSERT_GE(indices[b], 0) << "a drifted stencil's block is missing";
}

TEST(ParticleSet, BlockSortIsAPermutationThatCanBeUndone) {
  const Exec& exec = test::exec();
  const Index n = 5000;
  const ParticleInit init =
      unit_particles(test::random_planes(n, 2 * kDx, 1.0f - 2 * kDx, 11), test::random_planes(n, -1.0f, 1.0f, 12));
  ParticleSet particles(exec.backend, init);
  particles.sort_by_block(exec, 1.0f / kDx);

  // Sorted: block keys of consecutive particles never decrease.
  const ParticleView view = particles.view();
  std::vector<float> x(3 * n);
  memory::copy(x.data(), Backend::Cpu, view.x.data(), exec.backend, x.size() * sizeof(float), exec.stream);
  std::uint64_t previous = 0;
  for (Index p = 0; p < n; ++p) {
    const QuadraticStencil<float> s(Vec3<float>(x[p], x[n + p], x[2 * n + p]), 1.0f / kDx);
    const std::uint64_t key = block_key(s.base[0] / kBlockSide, s.base[1] / kBlockSide, s.base[2] / kBlockSide);
    ASSERT_GE(key, previous) << "particle " << p;
    previous = key;
  }
  EXPECT_EQ(particles.positions_in_initial_order(exec), init.x);
  EXPECT_EQ(particles.velocities_in_initial_order(exec), init.v);
}

}  // namespace
}  // namespace romp::mpm
