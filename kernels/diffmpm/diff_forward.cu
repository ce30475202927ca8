// Forward pass of the differentiable substep: P2G, grid update with walls and gravity, G2P to F_trial.
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/diffmpm/transfer_math.h"

namespace romp::diffmpm {
namespace {

template <class T>
struct ZeroScalars {
  Span<T> data;
  ROMP_HD void operator()(Index i) const { data[i] = T(0); }
};

// Alg. 3 step 1: m_i = Σ w M_p, q_i = Σ w (M_p v_p + A_p (x_i − x_p)) with A_p = k P Fᵀ + M_p C_p.
template <class T>
struct ParticleToGrid {
  StepParams<T> step;
  ParticleInputs<T> in;
  DenseGridView<T> grid;

  ROMP_HD void operator()(Index p) const {
    const T mass = in.mass[p];
    const Mat3<T> affine = particle_affine(step, in, p);
    const Vec3<T> momentum = mass * in.v.load(p);
    const mpm::QuadraticStencil<T> stencil(in.x.load(p), inverse_dx(step));
    for_each_stencil_node(step, grid, stencil, [&](const StencilNode<T>& node) {
      romp::atomic_add(&grid.mass[node.index], node.weight * mass);
      atomic_add(grid.momentum, node.index, mpm::node_momentum(node.weight, momentum, affine, node.offset));
    });
  }
};

// Alg. 3 step 2: v_i = walls(q_i / m_i + dt g); massless nodes stay at rest (no particle reads them
// with a non-zero weight).
template <class T>
struct UpdateGrid {
  StepParams<T> step;
  DenseGridView<T> grid;

  ROMP_HD void operator()(Index n) const {
    Vec3<T> v = Vec3<T>::zero();
    if (grid.mass[n] > T(0)) {
      const NodeUpdate<T> node = node_update(step, grid, n);
      v = hadamard(node.kept, node.velocity.free);
    }
    grid.velocity.store(n, v);
  }
};

// Alg. 3 steps 3–4: v' = Σ w v_i, C' = D⁻¹ Σ w v_i (x_i − x_p)ᵀ, F_trial' = (I + dt C') F, x' = x + dt v'.
template <class T>
struct GridToParticle {
  StepParams<T> step;
  ParticleInputs<T> in;
  DenseGridView<T> grid;
  StateView<T> out;

  ROMP_HD void operator()(Index p) const {
    Vec3<T> x = in.x.load(p);
    const GatheredVelocity<T> gathered = gather_velocity(step, grid, mpm::QuadraticStencil<T>(x, inverse_dx(step)));
    x += step.dt * gathered.v;
    out.x.store(p, mpm::kept_inside_domain(step.domain, x, step.dx));
    out.v.store(p, gathered.v);
    out.C.store(p, gathered.C);
    out.F.store(p, (Mat3<T>::identity() + step.dt * gathered.C) * in.F.load(p));
  }
};

}  // namespace

template <class T>
void grid_forward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch) {
  const Index nodes = dense_grid_nodes(params.domain.cells);
  ROMP_CHECK(scratch.size() == kDenseGridPlanes * nodes, "diffmpm: scratch of " + std::to_string(scratch.size()) +
                                                             " scalars, the grid needs " +
                                                             std::to_string(kDenseGridPlanes * nodes));
  const DenseGridView<T> grid(params.domain.cells, scratch);
  for_each(exec, scratch.size(), ZeroScalars<T>{scratch});
  for_each(exec, in.count, ParticleToGrid<T>{params, in, grid});
  for_each(exec, nodes, UpdateGrid<T>{params, grid});
}

template <class T>
void step_forward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch,
                  const StateView<T>& out) {
  grid_forward(exec, params, in, scratch);
  for_each(exec, in.count, GridToParticle<T>{params, in, DenseGridView<T>(params.domain.cells, scratch), out});
}

#define ROMP_DIFFMPM_FORWARD(T)                                                                        \
  template void grid_forward<T>(const Exec&, const StepParams<T>&, const ParticleInputs<T>&, Span<T>); \
  template void step_forward<T>(const Exec&, const StepParams<T>&, const ParticleInputs<T>&, Span<T>,  \
                                const StateView<T>&);
ROMP_DIFFMPM_FORWARD(float)
ROMP_DIFFMPM_FORWARD(double)
#undef ROMP_DIFFMPM_FORWARD

}  // namespace romp::diffmpm
