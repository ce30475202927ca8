// Adjoint pass of the differentiable substep: G2P, grid-update and P2G adjoints, in reverse order.
//
// Notation: a bar is ∂L/∂(·); w = w_ip, d = x_i − x_p, ∇w = ∂w/∂x_p (StencilGradient), and the
// forward quantities are those of diff_forward.cu. Every weight and offset depends on x_p, which is
// why each stage adds a term to x̄_p.
#include "kernels/core/for_each.h"
#include "kernels/diffmpm/transfer_math.h"

namespace romp::diffmpm {
namespace {

// Adjoint of x' = clamp(x + dt v'), v' = Σ w v_i, C' = D⁻¹ Σ w v_i dᵀ, F' = (I + dt C') F.
// With v̄* = v̄' + dt x̄' (x̄' zeroed where the clamp is active) and B̄ = D⁻¹ (C̄' + dt F̄' Fᵀ):
//   v̄_i += w (v̄* + B̄ d)                                (scattered: the forward gathered)
//   F̄    = (I + dt C')ᵀ F̄'
//   x̄    = x̄' + Σ ∇w (v̄*·v_i + v_iᵀ B̄ d) − w B̄ᵀ v_i    (d = x_i − x_p moves against x_p)
template <class T>
struct GridToParticleAdjoint {
  StepParams<T> step;
  ParticleInputs<T> in;
  DenseGridView<T> grid;
  StateView<const T> out_adjoint;
  InputAdjoints<T> in_adjoint;

  ROMP_HD void operator()(Index p) const {
    const Vec3<T> x = in.x.load(p);
    const Mat3<T> F = in.F.load(p);
    const mpm::QuadraticStencil<T> stencil(x, inverse_dx(step));
    const GatheredVelocity<T> gathered = gather_velocity(step, grid, stencil);

    const Vec3<T> moved = x + step.dt * gathered.v;
    Vec3<T> x_bar = out_adjoint.x.load(p);
    for (int a = 0; a < 3; ++a)
      if (moved[a] < step.domain.low_bound(step.dx) || moved[a] > step.domain.high_bound(a, step.dx)) x_bar[a] = T(0);
    const Vec3<T> v_bar = out_adjoint.v.load(p) + step.dt * x_bar;
    const Mat3<T> F_bar = out_adjoint.F.load(p);
    in_adjoint.F.store(p, transpose_times(Mat3<T>::identity() + step.dt * gathered.C, F_bar));
    const Mat3<T> B_bar = inverse_inertia(step) * (out_adjoint.C.load(p) + step.dt * times_transpose(F_bar, F));
    const Mat3<T> B_bar_t = transpose(B_bar);

    const StencilGradient<T> gradient(stencil, inverse_dx(step));
    for_each_stencil_node(step, grid, stencil, [&](const StencilNode<T>& node) {
      const Vec3<T> v_node = grid.velocity.load(node.index);
      const Vec3<T> node_bar = v_bar + B_bar * node.offset;
      atomic_add(grid.velocity_adjoint, node.index, node.weight * node_bar);
      x_bar += dot(node_bar, v_node) * gradient(stencil, node) - node.weight * (B_bar_t * v_node);
    });
    in_adjoint.x.store(p, x_bar);
  }
};

// Adjoint of v_i = M (q_i / m_i + dt g), M the wall mask (constant almost everywhere):
//   q̄_i = M v̄_i / m_i,  m̄_i = −(M v̄_i)·(q_i / m_i) / m_i.
// Written over the node's velocity adjoint (now q̄_i) and its mass adjoint.
template <class T>
struct UpdateGridAdjoint {
  StepParams<T> step;
  DenseGridView<T> grid;

  ROMP_HD void operator()(Index n) const {
    Vec3<T> momentum_bar = Vec3<T>::zero();
    T mass_bar = T(0);
    if (grid.mass[n] > T(0)) {
      const NodeUpdate<T> node = node_update(step, grid, n);
      const T inverse_mass = T(1) / grid.mass[n];
      const Vec3<T> v_free_bar = hadamard(node.kept, grid.velocity_adjoint.load(n));
      momentum_bar = inverse_mass * v_free_bar;
      mass_bar = -dot(v_free_bar, node.velocity.transferred) * inverse_mass;
    }
    grid.velocity_adjoint.store(n, momentum_bar);
    grid.mass_adjoint[n] = mass_bar;
  }
};

// Adjoint of m_i += w M_p and q_i += w (M_p v_p + A d), A = k P Fᵀ + M_p C (k = stress_factor):
//   v̄ = M_p Σ w q̄_i,  Ā = Σ w q̄_i dᵀ,  C̄ = M_p Ā,  P̄ = k Ā F,  F̄ += k Āᵀ P,
//   x̄ += Σ ∇w (q̄_i·(M_p v_p + A d) + M_p m̄_i) − w Aᵀ q̄_i.
// Runs after GridToParticleAdjoint, whose F̄ and x̄ it completes (same particle, no race).
template <class T>
struct ParticleToGridAdjoint {
  StepParams<T> step;
  ParticleInputs<T> in;
  DenseGridView<T> grid;
  InputAdjoints<T> in_adjoint;

  ROMP_HD void operator()(Index p) const {
    const T mass = in.mass[p];
    const Vec3<T> momentum = mass * in.v.load(p);
    const Mat3<T> affine = particle_affine(step, in, p);
    const Mat3<T> affine_t = transpose(affine);
    const mpm::QuadraticStencil<T> stencil(in.x.load(p), inverse_dx(step));
    const StencilGradient<T> gradient(stencil, inverse_dx(step));

    Vec3<T> x_bar = in_adjoint.x.load(p);
    Vec3<T> momentum_bar = Vec3<T>::zero();
    Mat3<T> affine_bar = Mat3<T>::zero();
    for_each_stencil_node(step, grid, stencil, [&](const StencilNode<T>& node) {
      const Vec3<T> node_bar = grid.velocity_adjoint.load(node.index);
      momentum_bar += node.weight * node_bar;
      affine_bar += Mat3<T>::outer(node.weight * node_bar, node.offset);
      x_bar += (dot(node_bar, momentum + affine * node.offset) + mass * grid.mass_adjoint[node.index]) *
                   gradient(stencil, node) -
               node.weight * (affine_t * node_bar);
    });
    const T k = stress_factor(step, in, p);
    in_adjoint.x.store(p, x_bar);
    in_adjoint.v.store(p, mass * momentum_bar);
    in_adjoint.C.store(p, mass * affine_bar);
    in_adjoint.P.store(p, k * (affine_bar * in.F.load(p)));
    in_adjoint.F.store(p, in_adjoint.F.load(p) + k * transpose_times(affine_bar, in.P.load(p)));
  }
};

}  // namespace

template <class T>
void step_backward(const Exec& exec, const StepParams<T>& params, const ParticleInputs<T>& in, Span<T> scratch,
                   const StateView<const T>& out_adjoint, const InputAdjoints<T>& in_adjoint) {
  // Recompute the grid (and zero its adjoint planes) from the step's inputs.
  grid_forward(exec, params, in, scratch);
  const DenseGridView<T> grid(params.domain.cells, scratch);
  for_each(exec, in.count, GridToParticleAdjoint<T>{params, in, grid, out_adjoint, in_adjoint});
  for_each(exec, grid.count, UpdateGridAdjoint<T>{params, grid});
  for_each(exec, in.count, ParticleToGridAdjoint<T>{params, in, grid, in_adjoint});
}

#define ROMP_DIFFMPM_BACKWARD(T)                                                                       \
  template void step_backward<T>(const Exec&, const StepParams<T>&, const ParticleInputs<T>&, Span<T>, \
                                 const StateView<const T>&, const InputAdjoints<T>&);
ROMP_DIFFMPM_BACKWARD(float)
ROMP_DIFFMPM_BACKWARD(double)
#undef ROMP_DIFFMPM_BACKWARD

}  // namespace romp::diffmpm
