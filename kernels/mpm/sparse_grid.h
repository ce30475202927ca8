// SparseGrid: 4x4x4 node blocks activated by the particles, found through a hash table of block keys.
//
// Memory is proportional to the blocks the particles touch, not to the domain's bounding box. The
// table is open addressing with linear probing, filled by concurrent inserts (compare-and-swap on
// the key); a block's index is handed out by an atomic counter, and its 64 nodes are stored at
// [64 index, 64 index + 64) of every node array. The same structure serves both backends.
#pragma once

#include <cstdint>
#include <functional>

#include "kernels/core/atomic.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/bspline.h"

namespace romp::mpm {

inline constexpr int kBlockSide = 4;
inline constexpr int kNodesPerBlock = kBlockSide * kBlockSide * kBlockSide;
// Keys carry bit 63 so that 0 can mark an empty slot (and a cleared table is a memset).
inline constexpr std::uint64_t kEmptyKey = 0;
inline constexpr std::uint64_t kKeyTag = std::uint64_t(1) << 63;
inline constexpr int kKeyBits = 21;  // per axis: block coordinates in [0, 2^21)
inline constexpr std::uint64_t kKeyMask = (std::uint64_t(1) << kKeyBits) - 1;
// The table keeps at most half its slots filled, so probe sequences stay short.
inline constexpr int kTableSlotsPerBlock = 2;

ROMP_HD_INLINE std::uint64_t block_key(int bx, int by, int bz) {
  return kKeyTag | (std::uint64_t(bx) << (2 * kKeyBits)) | (std::uint64_t(by) << kKeyBits) | std::uint64_t(bz);
}
ROMP_HD_INLINE int block_coordinate(std::uint64_t key, int axis) {
  return int((key >> ((2 - axis) * kKeyBits)) & kKeyMask);
}
// The key of the block that holds the stencil base node of a particle at x: what ParticleSet::sort_by_block
// orders the particles by.
ROMP_HD_INLINE std::uint64_t particle_block_key(const Vec3<float>& x, float inverse_dx) {
  int block[3];
  for (int a = 0; a < 3; ++a) block[a] = QuadraticStencil<float>::base_node(x[a] * inverse_dx) / kBlockSide;
  return block_key(block[0], block[1], block[2]);
}
// Node (i, j, k) lives in block (i/4, j/4, k/4) at local index 16 (i%4) + 4 (j%4) + k%4.
ROMP_HD_INLINE int local_node(int i, int j, int k) {
  return (i & (kBlockSide - 1)) * kBlockSide * kBlockSide + (j & (kBlockSide - 1)) * kBlockSide +
         (k & (kBlockSide - 1));
}

// The grid SparseGrid::rebuild_around_blocks builds holds the 27 blocks around each particle's block at the
// last sort: a stencil based at `base` (its node 0, 3 nodes per axis) lies in them while base - 4 b stays in
// [-4, 5] on each axis, b the block `sorted_key` names. The particle may drift 4 nodes down or 2 up.
ROMP_HD_INLINE bool stencil_within_blocks_around(const int base[3], std::uint64_t sorted_key) {
  for (int a = 0; a < 3; ++a) {
    const int offset = base[a] - kBlockSide * block_coordinate(sorted_key, a);
    if (base[a] < 0 || offset < -kBlockSide || offset > 2 * kBlockSide - 3) return false;
  }
  return true;
}

// splitmix64's finaliser: neighbouring blocks land far apart in the table.
ROMP_HD_INLINE std::uint64_t hash_key(std::uint64_t key) {
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  return key ^ (key >> 31);
}

// What kernels see of the table: plain spans, no ownership.
struct BlockTableView {
  Span<std::uint64_t> keys;        // capacity slots, kEmptyKey where free
  Span<std::int32_t> slot_block;   // block index stored in each filled slot
  Span<std::uint64_t> block_keys;  // key of each block index (max_blocks)
  // [0] blocks handed out, [1] set when an insert found no room, [2] the nodes of the blocks handed out (what
  // the CPU's node loops read: for_each_bounded).
  Span<std::int64_t> counters;
  std::uint64_t mask = 0;  // capacity - 1 (capacity is a power of two)

  // Inserts `key` if absent. Safe to call concurrently; never blocks on a full table.
  ROMP_HD void insert(std::uint64_t key) const {
    std::uint64_t slot = hash_key(key) & mask;
    for (std::uint64_t probe = 0; probe <= mask; ++probe) {
      const std::uint64_t seen = atomic_cas(&keys[Index(slot)], kEmptyKey, key);
      if (seen == kEmptyKey) {
        const std::int64_t block = atomic_add(&counters[0], std::int64_t(1));
        atomic_add(&counters[2], std::int64_t(kNodesPerBlock));
        if (block < block_keys.size()) block_keys[block] = key;
        slot_block[Index(slot)] = std::int32_t(block);
        return;
      }
      if (seen == key) return;
      slot = (slot + 1) & mask;
    }
    counters[1] = 1;
  }

  // The block index of `key`, or -1. Only valid after the inserting launch has finished.
  ROMP_HD std::int32_t find(std::uint64_t key) const {
    std::uint64_t slot = hash_key(key) & mask;
    for (std::uint64_t probe = 0; probe <= mask; ++probe) {
      const std::uint64_t seen = keys[Index(slot)];
      if (seen == key) return slot_block[Index(slot)];
      if (seen == kEmptyKey) return -1;
      slot = (slot + 1) & mask;
    }
    return -1;
  }
};

// The node data of the active blocks: mass, momentum (velocity after the grid update) and, for
// PIC/FLIP, the velocity before the update. Planes have stride `node_capacity`.
struct GridView {
  BlockTableView table;
  Span<float> mass;
  Vec3Planes<float> velocity;      // momentum during P2G, velocity after the grid update
  Vec3Planes<float> velocity_old;  // PIC/FLIP only (empty otherwise): velocity before forces
  // Active blocks this step, or an upper bound on them where the count stayed on the device
  // (SparseGrid::rebuild_for_few_points): node kernels run over `blocks` and skip what holds_node denies.
  Index blocks = 0;
  float dx = 0.0f;
  float inverse_dx = 0.0f;

  // Whether node n lies in an active block, by the device's count of them.
  ROMP_HD bool holds_node(Index n) const { return n < Index(table.counters[2]); }
  // The nodes of the active blocks, on the device: node kernels run for_each_bounded over blocks' nodes with it,
  // so that the CPU loops over the live nodes alone where `blocks` is a bound.
  Span<const std::int64_t> live_nodes() const { return table.counters.subspan(2, 1); }
  // Whether transfers also record the velocity before forces (for FLIP, of particles or of domain corners).
  ROMP_HD bool keeps_old_velocity() const { return velocity_old.data() != nullptr; }
};

// Owner of the table and the node arrays: rebuilt from the particle positions every substep, or around the
// sorted particles' blocks with each sort and kept until a particle leaves them (FullOrderSim::grid_follows_sort).
class SparseGrid {
 public:
  SparseGrid(Backend backend, float dx, bool keep_old_velocity);

  // Activates every block that the quadratic stencil of a point of `positions` or `more_positions`
  // (particles, and the corners of particle domains) touches and zeroes its nodes. Grows the table
  // (and retries) when the points touch more blocks than it holds.
  void rebuild(const Exec& exec, Vec3Planes<const float> positions, Vec3Planes<const float> more_positions = {});
  // Activates the 27 blocks around each block of particles the last sort found (run r of `sorted_keys`
  // starts at block_starts[r]; ParticleSet::sort_by_block's) and zeroes their nodes: a grid for the substeps
  // until a particle's stencil leaves them (stencil_within_blocks_around). Grows the table like rebuild.
  void rebuild_around_blocks(const Exec& exec, Span<const std::int32_t> block_starts,
                             Span<const std::uint64_t> sorted_keys);
  // rebuild for at most kFewPoints points with no round trip: storage for 8 blocks per point (a stencil
  // spans at most 2 blocks per axis) cannot overflow, so the count is not read back; the grid's node
  // kernels run over that bound and skip the nodes of blocks the device did not hand out
  // (GridView::holds_node). A reduced substep's grid, built from its few samples.
  static constexpr Index kFewPoints = 4096;
  void rebuild_for_few_points(const Exec& exec, Vec3Planes<const float> positions);
  // Zeroes the active blocks' nodes: the start of a substep that keeps the last rebuild's blocks.
  void clear_nodes(const Exec& exec);

  GridView view();
  // After rebuild_for_few_points, upper bounds (the count is on the device).
  Index active_blocks() const { return blocks_; }
  Index active_nodes() const { return blocks_ * kNodesPerBlock; }
  // The active blocks' nodes as the device counted them: a download.
  Index counted_nodes(const Exec& exec) const;
  // Bytes held by the table and node arrays (for memory-per-particle reports).
  std::size_t bytes() const;

 private:
  void allocate(Index max_blocks);
  // Clears the table, runs `activate` on it and reads the block count back; grows the table and runs it
  // again when the blocks did not fit. Then zeroes the active nodes.
  void activate_blocks(const Exec& exec, const std::function<void(const BlockTableView&)>& activate);

  Backend backend_;
  float dx_;
  bool keep_old_velocity_;
  Index max_blocks_ = 0;
  Index blocks_ = 0;
  DeviceBuffer<std::uint64_t> keys_;
  DeviceBuffer<std::int32_t> slot_block_;
  DeviceBuffer<std::uint64_t> block_keys_;
  DeviceBuffer<std::int64_t> counters_;
  DeviceBuffer<float> mass_;
  DeviceBuffer<float> velocity_;
  DeviceBuffer<float> velocity_old_;
};

}  // namespace romp::mpm
