// SparseGrid: block activation from particle stencils, with growth on overflow.
#include "kernels/mpm/sparse_grid.h"

#include <algorithm>
#include <string>

#include "kernels/core/for_each.h"
#include "kernels/mpm/bspline.h"

namespace romp::mpm {
namespace {

// Blocks to provision before the first rebuild has counted them (grows on demand).
constexpr Index kInitialBlocks = 256;
// Storage is shrunk when it exceeds the active blocks by this factor (and grown by 2 when short).
constexpr Index kShrinkFactor = 8;

// Inserts every block of the box [low, high] (block coordinates, inclusive on each axis).
ROMP_HD_INLINE void insert_block_box(const BlockTableView& table, const int low[3], const int high[3]) {
  for (int bx = low[0]; bx <= high[0]; ++bx)
    for (int by = low[1]; by <= high[1]; ++by)
      for (int bz = low[2]; bz <= high[2]; ++bz) table.insert(block_key(bx, by, bz));
}

struct ActivateStencilBlocks {
  Vec3Planes<const float> positions;
  BlockTableView table;
  float inverse_dx;

  ROMP_HD void operator()(Index p) const {
    const QuadraticStencil<float> stencil(positions.load(p), inverse_dx);
    int low[3], high[3];
    for (int a = 0; a < 3; ++a) {
      low[a] = stencil.base[a] / kBlockSide;         // base >= 0 inside the domain
      high[a] = (stencil.base[a] + 2) / kBlockSide;  // the stencil spans 3 nodes: at most 2 blocks per axis
    }
    insert_block_box(table, low, high);
  }
};

// One thread per run of sorted particles: the run's block and its 26 neighbours (none below coordinate 0,
// where no stencil reaches).
struct ActivateBlocksAround {
  Span<const std::int32_t> block_starts;
  Span<const std::uint64_t> sorted_keys;
  BlockTableView table;

  ROMP_HD void operator()(Index run) const {
    if (block_starts[run] == block_starts[run + 1]) return;  // past the runs (ParticleSet::RunCount::OnDevice)
    const std::uint64_t key = sorted_keys[block_starts[run]];
    int low[3], high[3];
    for (int a = 0; a < 3; ++a) {
      low[a] = block_coordinate(key, a) > 0 ? block_coordinate(key, a) - 1 : 0;
      high[a] = block_coordinate(key, a) + 1;
    }
    insert_block_box(table, low, high);
  }
};

// Zeroes every plane of an active node in one launch (a memset per plane was 4 or 7 stream operations).
struct ClearNode {
  GridView grid;
  ROMP_HD void operator()(Index n) const {
    if (!grid.holds_node(n)) return;
    grid.mass[n] = 0.0f;
    grid.velocity.store(n, Vec3<float>::zero());
    if (grid.keeps_old_velocity()) grid.velocity_old.store(n, Vec3<float>::zero());
  }
};

Index next_power_of_two(Index n) {
  Index p = 1;
  while (p < n) p <<= 1;
  return p;
}

}  // namespace

SparseGrid::SparseGrid(Backend backend, float dx, bool keep_old_velocity)
    : backend_(backend), dx_(dx), keep_old_velocity_(keep_old_velocity) {
  ROMP_CHECK(dx > 0.0f, "grid spacing must be positive");
  counters_ = DeviceBuffer<std::int64_t>(backend_, 3);
  allocate(kInitialBlocks);
}

void SparseGrid::allocate(Index max_blocks) {
  max_blocks_ = max_blocks;
  const Index slots = next_power_of_two(max_blocks * kTableSlotsPerBlock);
  keys_ = DeviceBuffer<std::uint64_t>(backend_, slots);
  slot_block_ = DeviceBuffer<std::int32_t>(backend_, slots);
  block_keys_ = DeviceBuffer<std::uint64_t>(backend_, max_blocks);
  const Index nodes = max_blocks * kNodesPerBlock;
  mass_ = DeviceBuffer<float>(backend_, nodes);
  velocity_ = DeviceBuffer<float>(backend_, 3 * nodes);
  velocity_old_ = DeviceBuffer<float>(backend_, keep_old_velocity_ ? 3 * nodes : 0);
}

GridView SparseGrid::view() {
  const Index nodes = max_blocks_ * kNodesPerBlock;
  GridView grid;
  grid.table = BlockTableView{keys_.span(), slot_block_.span(), block_keys_.span(), counters_.span(),
                              std::uint64_t(keys_.size() - 1)};
  grid.mass = mass_.span();
  grid.velocity = Vec3Planes<float>(velocity_.data(), nodes);
  grid.velocity_old = Vec3Planes<float>(keep_old_velocity_ ? velocity_old_.data() : nullptr, nodes);
  grid.blocks = blocks_;
  grid.dx = dx_;
  grid.inverse_dx = 1.0f / dx_;
  return grid;
}

void SparseGrid::rebuild(const Exec& exec, Vec3Planes<const float> positions, Vec3Planes<const float> more_positions) {
  activate_blocks(exec, [&](const BlockTableView& table) {
    for (const Vec3Planes<const float>& points : {positions, more_positions})
      for_each(exec, points.count(), ActivateStencilBlocks{points, table, 1.0f / dx_});
  });
}

void SparseGrid::rebuild_around_blocks(const Exec& exec, Span<const std::int32_t> block_starts,
                                       Span<const std::uint64_t> sorted_keys) {
  ROMP_CHECK(!block_starts.empty(), "rebuild_around_blocks needs the runs' starts and the end");
  activate_blocks(exec, [&](const BlockTableView& table) {
    for_each(exec, block_starts.size() - 1, ActivateBlocksAround{block_starts, sorted_keys, table});
  });
}

void SparseGrid::rebuild_for_few_points(const Exec& exec, Vec3Planes<const float> positions) {
  ROMP_CHECK(positions.count() <= kFewPoints, "rebuild_for_few_points takes at most " + std::to_string(kFewPoints) +
                                                  " points, got " + std::to_string(positions.count()));
  const Index bound = std::max(kInitialBlocks, 8 * positions.count());
  if (max_blocks_ < bound) allocate(bound);  // only when the points outnumber every earlier call's
  keys_.fill_zero(exec.stream);
  counters_.fill_zero(exec.stream);
  for_each(exec, positions.count(), ActivateStencilBlocks{positions, view().table, 1.0f / dx_});
  blocks_ = max_blocks_;
  clear_nodes(exec);
}

void SparseGrid::activate_blocks(const Exec& exec, const std::function<void(const BlockTableView&)>& activate) {
  // Give memory back once the particles occupy far fewer blocks than provisioned (after a splash
  // settles, say): memory follows the occupied blocks in both directions.
  if (blocks_ > 0 && blocks_ * kShrinkFactor < max_blocks_ && max_blocks_ > kInitialBlocks)
    allocate(std::max<Index>(kInitialBlocks, 2 * blocks_));
  while (true) {
    keys_.fill_zero(exec.stream);
    counters_.fill_zero(exec.stream);
    activate(view().table);
    const std::vector<std::int64_t> counters = counters_.to_host(exec.stream);
    if (counters[1] == 0 && counters[0] <= max_blocks_) {
      blocks_ = counters[0];
      break;
    }
    allocate(std::max<Index>(2 * max_blocks_, 2 * counters[0]));
  }
  clear_nodes(exec);
}

void SparseGrid::clear_nodes(const Exec& exec) {
  const GridView grid = view();
  for_each_bounded(exec, active_nodes(), grid.live_nodes(), ClearNode{grid});
}

Index SparseGrid::counted_nodes(const Exec& exec) const { return Index(counters_.to_host(exec.stream)[2]); }

std::size_t SparseGrid::bytes() const {
  return keys_.bytes() + slot_block_.bytes() + block_keys_.bytes() + counters_.bytes() + mass_.bytes() +
         velocity_.bytes() + velocity_old_.bytes();
}

}  // namespace romp::mpm
