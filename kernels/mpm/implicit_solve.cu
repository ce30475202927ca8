// The implicit step's grid operator as single-source functors: particles gather δu and scatter
// V⁰ δP Fᵀ ∇w (kernels/math/scatter.h), as P2G scatters its forces; nodes finish the products. See
// implicit_solve.h.
#include "kernels/mpm/implicit_solve.h"

#include <cstdint>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#include "kernels/math/atomic_planes.h"
#include "kernels/math/scatter.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/grid_boundary.h"
#include "kernels/mpm/mls_transfer.h"
#include "kernels/mpm/stencil_nodes.h"

namespace romp::mpm {
namespace {

using material::PrincipalStiffness;

// A particle's stencil with its nodes and the MLS weight gradients ∇w_ip = w_ip D⁻¹ (x_i − x_p).
struct ParticleStencil {
  QuadraticStencil<float> stencil;
  StencilNodes nodes;
  float d_inverse;  // D⁻¹ (mls_transfer.h)
  float dx;

  ROMP_HD ParticleStencil(const ParticleView& particles, const GridView& grid, Index p)
      : stencil(particles.x.load(p), grid.inverse_dx),
        nodes(stencil, grid.table),
        d_inverse(inverse_inertia(grid.inverse_dx)),
        dx(grid.dx) {}

  ROMP_HD Vec3<float> weight_gradient(int i, int j, int k) const {
    return (stencil.weight(i, j, k) * d_inverse) * stencil.offset(i, j, k, dx);
  }
};

// The flat vectors of implicit_solve.h: component a of entry n at a · entries + n (nodes first, then
// the domain corners).
ROMP_HD_INLINE Vec3Planes<float> entry_vectors(Span<float> flat, Index entries) {
  return Vec3Planes<float>(flat.data(), entries);
}
ROMP_HD_INLINE Vec3Planes<const float> entry_vectors(Span<const float> flat, Index entries) {
  return Vec3Planes<const float>(flat.data(), entries);
}

struct LineariseParticles {
  ParticleView particles;
  StepParams step;
  Span<PrincipalStiffness<float>> stiffness;

  ROMP_HD void operator()(Index p) const {
    if (particles.dirichlet_group[p] != kNoDirichletGroup) {
      const Mat3<float> I = Mat3<float>::identity();
      stiffness[p] = PrincipalStiffness<float>{I, I, Mat3<float>::zero(), Vec3<float>::zero(), Vec3<float>::zero()};
      return;
    }
    stiffness[p] = material::definite_stiffness(step.materials[particles.material[p]], particles.F.load(p));
  }
};

// The mass of entry n: the node's, or an enriched corner's; 0 for a corner bound to the grid or to
// a Dirichlet group (not an unknown).
ROMP_HD_INLINE float entry_mass(const GridView& grid, const DomainView& domains, Index nodes, Index n) {
  if (n < nodes) return grid.mass[n];
  const Index c = n - nodes;
  return domains.enriched[c] && domains.dirichlet_group[c] == kNoDirichletGroup ? domains.mass[c] : 0.0f;
}

// The directions a node's velocity is held along, as an orthonormal basis, and the projector onto
// the rest.
struct HeldDirections {
  Vec3<float> basis[3];
  int count = 0;

  // Adds unit direction d unless it (nearly) lies in the held span already.
  ROMP_HD void hold(Vec3<float> d) {
    for (int i = 0; i < count; ++i) d = d - dot(basis[i], d) * basis[i];
    const float length = norm(d);
    if (count < 3 && length > 1e-3f) basis[count++] = (1.0f / length) * d;
  }
  ROMP_HD void hold_all() {
    for (int a = 0; a < 3; ++a) basis[a] = Vec3<float>::unit(a);
    count = 3;
  }
  // S = I − Σ q qᵀ.
  ROMP_HD Mat3<float> projector() const {
    Mat3<float> S = Mat3<float>::identity();
    for (int i = 0; i < count; ++i) S = S - Mat3<float>::outer(basis[i], basis[i]);
    return S;
  }
};

// Holds what the walls and colliders fix for an unknown at `position` whose explicit velocity is v.
ROMP_HD_INLINE void hold_boundaries(const StepParams& step, const Vec3<float>& position, float dx, const Vec3<float>& v,
                                    HeldDirections& held) {
  for (Index c = 0; c < step.colliders.size(); ++c) {
    const ColliderState& collider = step.colliders[c];
    const SignedDistance sd = signed_distance(collider, position);
    if (sd.distance >= 0.0f) continue;
    const bool separating = dot(v - collider.velocity_at(position), sd.normal) > 0.0f;
    if (collider.contact == ContactType::Sticky)
      held.hold_all();
    else if (!(collider.contact == ContactType::Separate && separating))
      held.hold(sd.normal);
  }
  for (int a = 0; a < 3; ++a) {
    const bool low = step.domain.near_low_wall(position[a], dx), high = step.domain.near_high_wall(a, position[a], dx);
    if (!(low || high)) continue;
    if (step.domain.wall_contact == ContactType::Sticky) held.hold_all();
    // Held unless v* moves away from the wall (inward normal +e_a on the low face, −e_a on the high one).
    if ((low && v[a] <= 0.0f) || (high && v[a] >= 0.0f)) held.hold(Vec3<float>::unit(a));
  }
}

struct FindProjectors {
  GridView grid;
  DomainView domains;
  StepParams step;
  Mat3Planes<float> projector;

  ROMP_HD void operator()(Index n) const {
    const Index nodes = grid.blocks * kNodesPerBlock;
    HeldDirections held;
    if (entry_mass(grid, domains, nodes, n) <= 0.0f) {
      held.hold_all();
    } else if (n < nodes) {
      hold_boundaries(step, GridNode(grid, n).position, grid.dx, grid.velocity.load(n), held);
    } else {
      hold_boundaries(step, domains.x.load(n - nodes), grid.dx, domains.v.load(n - nodes), held);
    }
    projector.store(n, held.projector());
  }
};

// What the passes over particles share: Dirichlet particles are skipped (they add no stiffness),
// and `Body` receives the particle's stencil, F, stiffness and Δt² V⁰.
template <class Body>
struct StiffnessPass {
  ImplicitSystem system;
  Body body;

  ROMP_HD void operator()(Index p) const {
    const ParticleView& particles = system.particles;
    // Domain particles reach the grid through their corners (the domain passes below).
    if (particles.dirichlet_group[p] != kNoDirichletGroup || particles.has_domain(p)) return;
    body(ParticleStencil(particles, system.grid, p), particles.F.load(p), system.stiffness[p],
         system.step.dt * system.step.dt * particles.volume0[p]);
  }
};

// Adds scale δF_a : δP(δF_a), δF_a = e_a cᵀ, to each component a of `node`'s diagonal entries: one
// particle's share of K_ii when c is the vector through which node i moves its F.
ROMP_HD_INLINE void add_diagonal_share(Span<float> diagonal, Index entries, Index node, const Vec3<float>& c,
                                       const PrincipalStiffness<float>& stiffness, float scale) {
  Vec3<float> share;
  for (int a = 0; a < 3; ++a)
    share[a] = scale * dot(stiffness.apply(Mat3<float>::outer(Vec3<float>::unit(a), c)).row(a), c);
  atomic_add(entry_vectors(diagonal, entries), node, share);
}

// Σ_p Δt² V⁰_p δF_a : δP(δF_a) into each node's components, δF_a = e_a (Fᵀ ∇w)ᵀ.
struct StiffnessDiagonal {
  Span<float> diagonal;
  Index entries;

  ROMP_HD void operator()(const ParticleStencil& s, const Mat3<float>& F, const PrincipalStiffness<float>& stiffness,
                          float scale) const {
    for_each_stencil_offset([&](int i, int j, int k) {
      add_diagonal_share(diagonal, entries, s.nodes.node(i, j, k), transpose(F) * s.weight_gradient(i, j, k), stiffness,
                         scale);
    });
  }
};

// The domain passes: corner displacements gathered from the grid, each domain particle's stiffness
// scattered to its corners, the corners' forces scattered to the grid (implicit_solve.h).
struct GatherCornerDisplacements {
  DomainView domains;
  GridView grid;
  Span<const float> x;
  Vec3Planes<float> displacement;
  Index nodes;

  ROMP_HD void operator()(Index c) const {
    Vec3<float> u = Vec3<float>::zero();
    const Vec3Planes<const float> x_entries = entry_vectors(x, nodes + domains.corners);
    if (domains.dirichlet_group[c] != kNoDirichletGroup) {
      // Follows its group's motion: no displacement from the unknowns.
    } else if (domains.enriched[c]) {
      u = x_entries.load(nodes + c);
    } else {
      const QuadraticStencil<float> stencil(domains.x.load(c), grid.inverse_dx);
      const StencilNodes nodes_of(stencil, grid.table);
      for_each_stencil_offset(
          [&](int i, int j, int k) { u += stencil.weight(i, j, k) * x_entries.load(nodes_of.node(i, j, k)); });
    }
    displacement.store(c, u);
  }
};

// Whether p is a domain particle whose stiffness enters through its corners.
ROMP_HD_INLINE bool stiff_domain_particle(const ParticleView& particles, Index p) {
  return particles.has_domain(p) && particles.dirichlet_group[p] == kNoDirichletGroup;
}

struct DomainStiffness {
  ImplicitSystem system;
  Scatter scatter;

  ROMP_HD void operator()(Index p) const {
    const ParticleView& particles = system.particles;
    if (!stiff_domain_particle(particles, p)) return;
    const DomainView& domains = system.domains;
    const Index d = particles.domain[p];
    Mat3<float> dF = Mat3<float>::zero();
    for (int a = 0; a < kDomainCorners; ++a) {
      const Index entry = kDomainCorners * d + a;
      dF += Mat3<float>::outer(system.corner_displacement.load(domains.corner[entry]), domains.gradient.load(entry));
    }
    const float scale = system.step.dt * system.step.dt * particles.volume0[p];
    const Mat3<float> stress = scale * system.stiffness[p].apply(dF);
    for (int a = 0; a < kDomainCorners; ++a) {
      const Index entry = kDomainCorners * d + a;
      scatter.add(system.corner_force, domains.corner[entry], stress * domains.gradient.load(entry));
    }
  }
};

struct ScatterCornerForces {
  DomainView domains;
  GridView grid;
  Vec3Planes<const float> force;
  Span<float> out;
  Index nodes;
  Scatter scatter;

  ROMP_HD void operator()(Index c) const {
    if (domains.dirichlet_group[c] != kNoDirichletGroup) return;
    const Vec3Planes<float> out_entries = entry_vectors(out, nodes + domains.corners);
    const Vec3<float> f = force.load(c);
    if (domains.enriched[c]) {
      out_entries.store(nodes + c, out_entries.load(nodes + c) + f);  // this thread's entry alone
      return;
    }
    const QuadraticStencil<float> stencil(domains.x.load(c), grid.inverse_dx);
    const StencilNodes nodes_of(stencil, grid.table);
    for_each_stencil_offset(
        [&](int i, int j, int k) { scatter.add(out_entries, nodes_of.node(i, j, k), stencil.weight(i, j, k) * f); });
  }
};

// Σ_p Δt² V⁰ δF_a : δP(δF_a), δF_a = e_a G_jᵀ, for a domain particle: G_j = Σ_α w_j(x_α) g_α sums
// over its grid-bound corners' stencils first (the corners share nodes, and Σ_α g_α = 0 makes the
// sum, not the single terms, what the particle feels); an enriched corner's entry has G = g_α. The
// union of the stencils fits a box of 5 nodes per axis unless the domain spans more than 3 cells;
// then each corner's term counts on its own, a cruder diagonal that is still positive, which is all
// the preconditioner needs.
struct DomainStiffnessDiagonal {
  ImplicitSystem system;
  Span<float> diagonal;

  static constexpr int kBox = 5;

  ROMP_HD void operator()(Index p) const {
    const ParticleView& particles = system.particles;
    if (!stiff_domain_particle(particles, p)) return;
    const DomainView& domains = system.domains;
    const GridView& grid = system.grid;
    const Index d = particles.domain[p];
    const PrincipalStiffness<float>& stiffness = system.stiffness[p];
    const float scale = system.step.dt * system.step.dt * particles.volume0[p];
    const Index nodes = system.nodes(), entries = system.entries();
    int low[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, high[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (int a = 0; a < kDomainCorners; ++a) {
      const QuadraticStencil<float> stencil(domains.x.load(domains.corner[kDomainCorners * d + a]), grid.inverse_dx);
      for (int axis = 0; axis < 3; ++axis) {
        low[axis] = math::min(low[axis], stencil.base[axis]);
        high[axis] = math::max(high[axis], stencil.base[axis]);
      }
    }
    const bool boxed = high[0] - low[0] <= kBox - 3 && high[1] - low[1] <= kBox - 3 && high[2] - low[2] <= kBox - 3;
    Vec3<float> G[kBox * kBox * kBox];
    Index node_of[kBox * kBox * kBox];
    if (boxed) {
      for (int b = 0; b < kBox * kBox * kBox; ++b) {
        G[b] = Vec3<float>::zero();
        node_of[b] = -1;
      }
    }
    for (int a = 0; a < kDomainCorners; ++a) {
      const Index entry = kDomainCorners * d + a;
      const Index c = domains.corner[entry];
      if (domains.dirichlet_group[c] != kNoDirichletGroup) continue;
      const Vec3<float> g = domains.gradient.load(entry);
      if (domains.enriched[c]) {
        add_diagonal_share(diagonal, entries, nodes + c, g, stiffness, scale);
        continue;
      }
      const QuadraticStencil<float> stencil(domains.x.load(c), grid.inverse_dx);
      const StencilNodes nodes_of(stencil, grid.table);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int k = 0; k < 3; ++k) {
            const Vec3<float> term = stencil.weight(i, j, k) * g;
            if (!boxed) {
              add_diagonal_share(diagonal, entries, nodes_of.node(i, j, k), term, stiffness, scale);
              continue;
            }
            const int b = ((stencil.base[0] + i - low[0]) * kBox + (stencil.base[1] + j - low[1])) * kBox +
                          (stencil.base[2] + k - low[2]);
            G[b] += term;
            node_of[b] = nodes_of.node(i, j, k);
          }
    }
    if (boxed)
      for (int b = 0; b < kBox * kBox * kBox; ++b)
        if (node_of[b] >= 0) add_diagonal_share(diagonal, entries, node_of[b], G[b], stiffness, scale);
  }
};

// Δt² K x of the domain particles, added to `out`.
void add_domain_stiffness(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> out) {
  const DomainView& domains = system.domains;
  if (domains.corners == 0) return;
  const Index nodes = system.nodes();
  for_each(exec, domains.corners,
           GatherCornerDisplacements{domains, system.grid, x, system.corner_displacement, nodes});
  for (int a = 0; a < 3; ++a)
    memory::fill_zero(system.corner_force.data() + a * domains.corners, exec.backend,
                      std::size_t(domains.corners) * sizeof(float), exec.stream);
  const Scatter scatter = Scatter::for_exec(exec);
  for_each(exec, system.particles.count, DomainStiffness{system, scatter});
  for_each(
      exec, domains.corners,
      ScatterCornerForces{domains, system.grid, Vec3Planes<const float>(system.corner_force), out, nodes, scatter});
}

struct InvertDiagonal {
  ImplicitSystem system;
  Span<float> diagonal;  // Δt² K_ii on entry, its inverse with the mass on exit

  ROMP_HD void operator()(Index n) const {
    const float mass = entry_mass(system.grid, system.domains, system.nodes(), n);
    for (int a = 0; a < 3; ++a) {
      const Index k = a * system.entries() + n;
      // Mass > 0 and K_ii ≥ 0, so the sum is > 0.
      diagonal[k] = mass > 0.0f ? 1.0f / (mass + diagonal[k]) : 0.0f;
    }
  }
};

struct ApplyPreconditioner {
  Mat3Planes<const float> projector;
  Span<const float> inverse_diagonal, r;
  Span<float> z;
  Index entries;

  ROMP_HD void operator()(Index n) const {
    const Vec3<float> d = entry_vectors(inverse_diagonal, entries).load(n);
    const Vec3<float> residual = entry_vectors(r, entries).load(n);
    entry_vectors(z, entries)
        .store(n, projector.load(n) * Vec3<float>(d[0] * residual[0], d[1] * residual[1], d[2] * residual[2]));
  }
};

// Δt² K x: each particle gathers δF = (Σ_j x_j ∇w_jpᵀ) F and scatters Δt² V⁰ δP Fᵀ ∇w_ip.
struct ApplyStiffness {
  Span<const float> x;
  Span<float> Kx;
  Index entries;
  Scatter scatter;

  ROMP_HD void operator()(const ParticleStencil& s, const Mat3<float>& F, const PrincipalStiffness<float>& stiffness,
                          float scale) const {
    const Vec3Planes<const float> x_entries = entry_vectors(x, entries);
    Mat3<float> displacement_gradient = Mat3<float>::zero();
    for_each_stencil_offset([&](int i, int j, int k) {
      displacement_gradient += Mat3<float>::outer(x_entries.load(s.nodes.node(i, j, k)), s.weight_gradient(i, j, k));
    });
    const Mat3<float> force_moment = scale * times_transpose(stiffness.apply(displacement_gradient * F), F);
    for_each_stencil_offset([&](int i, int j, int k) {
      scatter.add(entry_vectors(Kx, entries), s.nodes.node(i, j, k), force_moment * s.weight_gradient(i, j, k));
    });
  }
};

struct FinishOperator {
  ImplicitSystem system;
  Span<const float> x;
  Span<float> Ax;  // Δt² K x on entry (zero for the mass alone)

  ROMP_HD void operator()(Index n) const {
    const Index entries = system.entries();
    const Vec3Planes<float> out = entry_vectors(Ax, entries);
    const float mass = entry_mass(system.grid, system.domains, system.nodes(), n);
    out.store(n, system.projector.load(n) * (mass * entry_vectors(x, entries).load(n) + out.load(n)));
  }
};

// v* of the unknowns into the flat vector (0 elsewhere).
struct LoadVelocities {
  ImplicitSystem system;
  Span<float> flat;

  ROMP_HD void operator()(Index n) const {
    const Index nodes = system.nodes();
    Vec3<float> v = Vec3<float>::zero();
    if (entry_mass(system.grid, system.domains, nodes, n) > 0.0f)
      v = n < nodes ? system.grid.velocity.load(n) : system.domains.v.load(n - nodes);
    entry_vectors(flat, system.entries()).store(n, v);
  }
};

// The unknowns' solution back to the grid and the enriched corners, through the walls and colliders.
struct StoreVelocities {
  ImplicitSystem system;
  Span<const float> flat;

  ROMP_HD void operator()(Index n) const {
    const GridView& grid = system.grid;
    const Index nodes = system.nodes();
    if (entry_mass(grid, system.domains, nodes, n) <= 0.0f) return;
    const Vec3<float> v = entry_vectors(flat, system.entries()).load(n);
    if (n < nodes)
      grid.velocity.store(n, resolve_boundaries(system.step, GridNode(grid, n), v));
    else
      system.domains.v.store(n - nodes, resolve_boundaries(system.step, system.domains.x.load(n - nodes), grid.dx, v));
  }
};

void check_entry_vector(Span<const float> v, const ImplicitSystem& system, const char* what) {
  ROMP_CHECK(v.size() == 3 * system.entries(),
             std::string(what) + " must hold 3 components per active grid node and domain corner");
}

// S (M x + Δt² K x), or S M x without the stiffness.
void apply_operator(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> out,
                    bool with_stiffness) {
  check_entry_vector(x, system, "x");
  check_entry_vector(out, system, "the operator's output");
  memory::fill_zero(out.data(), exec.backend, out.size() * sizeof(float), exec.stream);
  if (with_stiffness) {
    for_each(exec, system.particles.count,
             StiffnessPass<ApplyStiffness>{system, ApplyStiffness{x, out, system.entries(), Scatter::for_exec(exec)}});
    add_domain_stiffness(exec, system, x, out);
  }
  for_each(exec, system.entries(), FinishOperator{system, x, out});
}

}  // namespace

void linearise_particles(const Exec& exec, const ParticleView& particles, const StepParams& step,
                         Span<PrincipalStiffness<float>> stiffness) {
  ROMP_CHECK(stiffness.size() == particles.count, "linearise_particles: one stiffness per particle");
  for_each(exec, particles.count, LineariseParticles{particles, step, stiffness});
}

void find_projectors(const Exec& exec, const GridView& grid, const DomainView& domains, const StepParams& step,
                     Mat3Planes<float> projector) {
  const Index entries = grid.blocks * kNodesPerBlock + domains.corners;
  ROMP_CHECK(projector.count() == entries, "find_projectors: one projector per active grid node and domain corner");
  for_each(exec, entries, FindProjectors{grid, domains, step, projector});
}

void jacobi_inverse_diagonal(const Exec& exec, const ImplicitSystem& system, Span<float> inverse_diagonal) {
  check_entry_vector(inverse_diagonal, system, "inverse_diagonal");
  memory::fill_zero(inverse_diagonal.data(), exec.backend, inverse_diagonal.size() * sizeof(float), exec.stream);
  for_each(exec, system.particles.count,
           StiffnessPass<StiffnessDiagonal>{system, StiffnessDiagonal{inverse_diagonal, system.entries()}});
  if (system.domains.corners > 0)
    for_each(exec, system.particles.count, DomainStiffnessDiagonal{system, inverse_diagonal});
  for_each(exec, system.entries(), InvertDiagonal{system, inverse_diagonal});
}

void apply_preconditioner(const Exec& exec, const ImplicitSystem& system, Span<const float> inverse_diagonal,
                          Span<const float> r, Span<float> z) {
  for (const Span<const float> v : {inverse_diagonal, r, Span<const float>(z)})
    check_entry_vector(v, system, "a preconditioner vector");
  for_each(exec, system.entries(), ApplyPreconditioner{system.projector, inverse_diagonal, r, z, system.entries()});
}

void apply_implicit_operator(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Ax) {
  apply_operator(exec, system, x, Ax, true);
}

void apply_mass(const Exec& exec, const ImplicitSystem& system, Span<const float> x, Span<float> Mx) {
  apply_operator(exec, system, x, Mx, false);
}

void load_explicit_velocities(const Exec& exec, const ImplicitSystem& system, Span<float> v) {
  check_entry_vector(v, system, "the velocity vector");
  for_each(exec, system.entries(), LoadVelocities{system, v});
}

void store_velocities(const Exec& exec, const ImplicitSystem& system, Span<const float> v) {
  check_entry_vector(v, system, "the velocity vector");
  for_each(exec, system.entries(), StoreVelocities{system, v});
}

}  // namespace romp::mpm
