// Maps a particle's 3x3x3 stencil to node indices of the sparse grid with 8 table look-ups, not 27.
#pragma once

#include "kernels/mpm/bspline.h"
#include "kernels/mpm/sparse_grid.h"

namespace romp::mpm {

struct StencilNodes {
  int base[3];
  int low_block[3];
  std::int32_t block[2][2][2];  // block index of (low_block + (a, b, c)), -1 if inactive

  ROMP_HD StencilNodes(const QuadraticStencil<float>& stencil, const BlockTableView& table) {
    for (int a = 0; a < 3; ++a) {
      base[a] = stencil.base[a];
      low_block[a] = base[a] / kBlockSide;
    }
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c)
          block[a][b][c] = table.find(block_key(low_block[0] + a, low_block[1] + b, low_block[2] + c));
  }

  // Index of node base + (i, j, k) in the grid's node arrays. Every block a stencil touches was
  // activated by SparseGrid::rebuild from the same positions, so the look-up always succeeds.
  ROMP_HD Index node(int i, int j, int k) const {
    const int n0 = base[0] + i, n1 = base[1] + j, n2 = base[2] + k;
    return Index(block_of(n0, n1, n2)) * kNodesPerBlock + local_node(n0, n1, n2);
  }

  // Whether node base + (i, j, k) lies in an active block: for points the grid was not built from.
  ROMP_HD bool active(int i, int j, int k) const { return block_of(base[0] + i, base[1] + j, base[2] + k) >= 0; }

 private:
  ROMP_HD std::int32_t block_of(int n0, int n1, int n2) const {
    return block[n0 / kBlockSide - low_block[0]][n1 / kBlockSide - low_block[1]][n2 / kBlockSide - low_block[2]];
  }
};

}  // namespace romp::mpm
