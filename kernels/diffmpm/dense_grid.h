// DenseGridView<T>: the (cells + 1)³ nodes of the differentiable step's grid, with their adjoints, as planes.
//
// The training scenes of Ma et al. 2023 are tiny (1000 particles on 20³ cells, 9261 nodes), so the
// differentiable step uses a dense grid: node look-ups are index arithmetic, no hash table or sort
// has to be differentiated or replayed, and the whole grid is one scratch allocation.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"

namespace romp::diffmpm {

// Scalar planes of one grid: mass, momentum (3), velocity (3), velocity adjoint (3), mass adjoint.
inline constexpr int kDenseGridPlanes = 11;

// The number of nodes of a dense grid over `cells` cells per axis.
inline Index dense_grid_nodes(const int cells[3]) {
  return Index(cells[0] + 1) * Index(cells[1] + 1) * Index(cells[2] + 1);
}

template <class T>
struct DenseGridView {
  int nodes[3];                    // cells + 1 per axis
  Index count;                     // nodes[0] nodes[1] nodes[2]
  Span<T> mass;                    // m_i (P2G)
  Vec3Planes<T> momentum;          // q_i = m_i v_i before the grid update (P2G)
  Vec3Planes<T> velocity;          // v_i after gravity and walls (grid update)
  Vec3Planes<T> velocity_adjoint;  // ∂L/∂v_i (G2P adjoint), overwritten by ∂L/∂q_i (grid adjoint)
  Span<T> mass_adjoint;            // ∂L/∂m_i (grid adjoint)

  // The planes of `scratch` (kDenseGridPlanes × dense_grid_nodes(cells) scalars), laid out in the order above.
  DenseGridView(const int cells[3], Span<T> scratch) {
    for (int a = 0; a < 3; ++a) nodes[a] = cells[a] + 1;
    count = dense_grid_nodes(cells);
    T* data = scratch.data();
    mass = Span<T>(data, count);
    momentum = Vec3Planes<T>(data + count, count);
    velocity = Vec3Planes<T>(data + 4 * count, count);
    velocity_adjoint = Vec3Planes<T>(data + 7 * count, count);
    mass_adjoint = Span<T>(data + 10 * count, count);
  }

  ROMP_HD Index index(int i, int j, int k) const { return (Index(i) * nodes[1] + j) * nodes[2] + k; }
  ROMP_HD void coordinates(Index n, int node[3]) const {
    node[2] = int(n % nodes[2]);
    node[1] = int(n / nodes[2] % nodes[1]);
    node[0] = int(n / (Index(nodes[1]) * nodes[2]));
  }
};

}  // namespace romp::diffmpm
