// Tiled P2G: the particles of one grid block (a run after sort_by_block) scatter into a local tile of
// the 6 × 6 × 6 nodes their stencils can reach, and the tile is added to the grid once (GPU MPM, Gao et
// al. 2018). A block of 512 particles then makes 216 × 4 grid atomics instead of 27 × 4 per particle.
// The sort need not be this substep's: a particle that has since left its run's block (its stencil would
// leave the tile) is skipped by the tiles and scattered straight to the grid by a second launch, as the
// portable kernel does, so the order only decides how many particles take the fast path. (The fallback
// inside the tile kernel cost it 47 registers and 56 bytes of stack more: the portable scatter's 27 node
// lookups live beside the tile's state.)
// The CPU runs one block per loop iteration with plain adds into the tile; CUDA runs one thread block
// per grid block with the tile in shared memory. Both share the tile arithmetic below with each other
// and the per-particle arithmetic (P2GParticle) with the portable kernel.
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/p2g_particle.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

// Nodes per tile axis: a particle's base node lies in the block's 4 nodes, its stencil reaches 2 more.
constexpr int kTileSide = kBlockSide + 2;
constexpr int kTileNodes = kTileSide * kTileSide * kTileSide;
// Tile planes: mass, momentum (3), and for PIC/FLIP the momentum before forces (3).
constexpr int kTilePlanes = 7;

ROMP_HD_INLINE int tile_node(int i, int j, int k) { return (i * kTileSide + j) * kTileSide + k; }

// Adds `value` to a tile entry: a plain add where one thread owns the tile, a shared-memory atomic
// where a thread block shares it.
template <bool kShared>
ROMP_HD_INLINE void tile_add(float* entry, float value) {
#if defined(__CUDA_ARCH__)
  if constexpr (kShared) {
    atomicAdd(entry, value);
    return;
  }
#endif
  *entry += value;
}

// The first node of the block a run was sorted into (its key): the tile's origin.
ROMP_HD_INLINE void tile_origin(std::uint64_t block, int origin[3]) {
  for (int a = 0; a < 3; ++a) origin[a] = block_coordinate(block, a) * kBlockSide;
}

// Whether the particle at x is no longer in the block of key `block` (particle_block_key's, compared by
// coordinate: building the key anew cost the second launch 13 registers).
ROMP_HD_INLINE bool left_block(const Vec3<float>& x, float inverse_dx, std::uint64_t block) {
  for (int a = 0; a < 3; ++a)
    if (QuadraticStencil<float>::base_node(x[a] * inverse_dx) / kBlockSide != block_coordinate(block, a)) return true;
  return false;
}

// A particle in the run of block `run_key` whose stencil base has since moved to another block (its
// stencil may leave the tile) is left to MovedParticleToGrid.
template <bool kShared>
ROMP_HD void scatter_to_tile(const ParticleView& particles, const GridView& grid, const StepParams& step, Index p,
                             std::uint64_t run_key, const int origin[3], float* tile) {
  if (particles.has_domain(p)) return;  // its domain's corners carry it to the grid
  if (left_block(particles.x.load(p), grid.inverse_dx, run_key)) return;
  const P2GParticle particle(particles, grid, step, p);
  const bool flip = grid.keeps_old_velocity();
  const int di = particle.stencil.base[0] - origin[0], dj = particle.stencil.base[1] - origin[1],
            dk = particle.stencil.base[2] - origin[2];
  for_each_stencil_offset([&](int i, int j, int k) {
    const int node = tile_node(di + i, dj + j, dk + k);
    const float w = particle.weight(i, j, k);
    const Vec3<float> contribution = particle.momentum_to(i, j, k, w, grid.dx);
    tile_add<kShared>(&tile[node], w * particle.mass);
    for (int a = 0; a < 3; ++a) tile_add<kShared>(&tile[(1 + a) * kTileNodes + node], contribution[a]);
    if (flip)
      for (int a = 0; a < 3; ++a)
        tile_add<kShared>(&tile[(4 + a) * kTileNodes + node], w * particle.mass * particle.v[a]);
  });
}

// Adds tile node `node` to the grid. Nodes no particle reached (mass 0) are skipped: their block may
// not even be active.
ROMP_HD void flush_tile_node(const GridView& grid, bool flip, const int origin[3], const float* tile, int node) {
  const float mass = tile[node];
  if (mass == 0.0f) return;
  const int i = origin[0] + node / (kTileSide * kTileSide), j = origin[1] + (node / kTileSide) % kTileSide,
            k = origin[2] + node % kTileSide;
  const std::int32_t block = grid.table.find(block_key(i / kBlockSide, j / kBlockSide, k / kBlockSide));
  const Index n = Index(block) * kNodesPerBlock + local_node(i, j, k);
  atomic_add(&grid.mass[n], mass);
  for (int a = 0; a < 3; ++a)
    atomic_add(&grid.velocity.data()[a * grid.velocity.count() + n], tile[(1 + a) * kTileNodes + node]);
  if (flip)
    for (int a = 0; a < 3; ++a)
      atomic_add(&grid.velocity_old.data()[a * grid.velocity_old.count() + n], tile[(4 + a) * kTileNodes + node]);
}

// CPU: one grid block per loop iteration, its tile on the stack.
struct TiledBlockToGrid {
  ParticleView particles;
  GridView grid;
  StepParams step;
  Span<const std::int32_t> starts;
  Span<const std::uint64_t> sorted_keys;
  void operator()(Index block) const {
    const Index begin = starts[block], end = starts[block + 1];
    if (begin == end) return;  // past the runs (ParticleSet::RunCount::OnDevice)
    float tile[kTilePlanes * kTileNodes] = {};
    int origin[3];
    tile_origin(sorted_keys[begin], origin);
    for (Index p = begin; p < end; ++p)
      scatter_to_tile<false>(particles, grid, step, p, sorted_keys[begin], origin, tile);
    const bool flip = grid.keeps_old_velocity();
    for (int node = 0; node < kTileNodes; ++node) flush_tile_node(grid, flip, origin, tile, node);
  }
};

// The particles the tiles skipped, with the portable kernel's scatter: one thread per particle, most of them
// returning after reading their position and key.
struct MovedParticleToGrid {
  ParticleView particles;
  GridView grid;
  StepParams step;
  Span<const std::uint64_t> sorted_keys;
  ROMP_HD void operator()(Index p) const {
    if (particles.has_domain(p)) return;
    if (left_block(particles.x.load(p), grid.inverse_dx, sorted_keys[p]))
      scatter_to_grid(P2GParticle(particles, grid, step, p), grid);
  }
};

#if defined(__CUDACC__)
constexpr int kTiledThreads = 128;

// CUDA: one thread block per grid block; its threads share the tile in shared memory.
__global__ void tiled_block_to_grid(ParticleView particles, GridView grid, StepParams step,
                                    Span<const std::int32_t> starts, Span<const std::uint64_t> sorted_keys) {
  const Index begin = starts[blockIdx.x], end = starts[blockIdx.x + 1];
  if (begin == end) return;  // past the runs (ParticleSet::RunCount::OnDevice): the whole thread block leaves
  __shared__ float tile[kTilePlanes * kTileNodes];
  for (int t = threadIdx.x; t < kTilePlanes * kTileNodes; t += blockDim.x) tile[t] = 0.0f;
  int origin[3];
  tile_origin(sorted_keys[begin], origin);
  __syncthreads();
  for (Index p = begin + threadIdx.x; p < end; p += blockDim.x)
    scatter_to_tile<true>(particles, grid, step, p, sorted_keys[begin], origin, tile);
  __syncthreads();
  const bool flip = grid.keeps_old_velocity();
  for (int node = threadIdx.x; node < kTileNodes; node += blockDim.x) flush_tile_node(grid, flip, origin, tile, node);
}
#endif

}  // namespace

void particle_to_grid_tiled(const Exec& exec, const ParticleView& particles, const GridView& grid,
                            const StepParams& step, Span<const std::int32_t> block_starts,
                            Span<const std::uint64_t> sorted_keys, bool sorted_at_these_positions) {
  const Index blocks = block_starts.size() - 1;
  ROMP_CHECK(blocks >= 0, "block_starts needs the particle count at its end");
  ROMP_CHECK(sorted_keys.size() == particles.count, "the sort's block key of every particle");
  if (blocks == 0) return;
  if (exec.is_cuda()) {
    memory::note_launch();
#if defined(__CUDACC__)
    tiled_block_to_grid<<<unsigned(blocks), kTiledThreads, 0, exec.stream>>>(particles, grid, step, block_starts,
                                                                             sorted_keys);
    romp::detail::check_launch(exec);
#else
    throw Error("particle_to_grid_tiled on CUDA from a translation unit not compiled by nvcc");
#endif
  } else {
    const int threads = romp::detail::cpu_threads(exec);
    const TiledBlockToGrid run{particles, grid, step, block_starts, sorted_keys};
    memory::launch_on_cpu(exec.stream, 1, [run, threads, blocks] {
      const memory::DeviceAccess launch;
      // Blocks hold very different particle counts: hand them out a few at a time.
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
      for (Index block = 0; block < blocks; ++block) run(block);
    });
  }
  if (!sorted_at_these_positions)
    for_each(exec, particles.count, MovedParticleToGrid{particles, grid, step, sorted_keys});
}

}  // namespace romp::mpm
