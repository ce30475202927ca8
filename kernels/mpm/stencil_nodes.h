// Maps a particle's 3x3x3 stencil to node indices of the sparse grid with 8 table look-ups, not 27.
#pragma once

#include "kernels/mpm/bspline.h"
#include "kernels/mpm/sparse_grid.h"

namespace romp::mpm {

// The 8 blocks are named by constant indices only and picked by selects: an array indexed at run time would
// put the whole object in local memory (ptxas: a 56-byte stack frame in every transfer kernel).
class StencilNodes {
 public:
  ROMP_HD StencilNodes(const QuadraticStencil<float>& stencil, const BlockTableView& table) {
    int low_block[3];
    for (int a = 0; a < 3; ++a) {
      base_[a] = stencil.base[a];
      low_block[a] = base_[a] / kBlockSide;
      // Stencil offsets i >= this lie in the next block along the axis (4 - base % 4, in [1, 4]).
      next_block_from_[a] = kBlockSide - base_[a] % kBlockSide;
    }
    const auto find = [&](int a, int b, int c) {
      return table.find(block_key(low_block[0] + a, low_block[1] + b, low_block[2] + c));
    };
    b000_ = find(0, 0, 0), b001_ = find(0, 0, 1), b010_ = find(0, 1, 0), b011_ = find(0, 1, 1);
    b100_ = find(1, 0, 0), b101_ = find(1, 0, 1), b110_ = find(1, 1, 0), b111_ = find(1, 1, 1);
  }

  // Index of node base + (i, j, k) in the grid's node arrays. Every block a stencil touches was
  // activated by SparseGrid::rebuild from the same positions (or around them, by rebuild_around_blocks),
  // so the look-up always succeeds.
  ROMP_HD Index node(int i, int j, int k) const {
    const int n0 = base_[0] + i, n1 = base_[1] + j, n2 = base_[2] + k;
    return Index(block_of(i, j, k)) * kNodesPerBlock + local_node(n0, n1, n2);
  }

  // Whether node base + (i, j, k) lies in an active block: for points the grid was not built from.
  ROMP_HD bool active(int i, int j, int k) const { return block_of(i, j, k) >= 0; }

 private:
  // The block index (-1 if inactive) of stencil node (i, j, k).
  ROMP_HD std::int32_t block_of(int i, int j, int k) const {
    const bool up0 = i >= next_block_from_[0], up1 = j >= next_block_from_[1], up2 = k >= next_block_from_[2];
    const std::int32_t low = up1 ? (up2 ? b011_ : b010_) : (up2 ? b001_ : b000_);
    const std::int32_t high = up1 ? (up2 ? b111_ : b110_) : (up2 ? b101_ : b100_);
    return up0 ? high : low;
  }

  int base_[3];
  int next_block_from_[3];
  // Block index of (low block + (a, b, c)), -1 if inactive.
  std::int32_t b000_, b001_, b010_, b011_, b100_, b101_, b110_, b111_;
};

}  // namespace romp::mpm
