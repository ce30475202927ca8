// The implicit step's grid operator A = M + Δt² K (kernels/mpm/implicit_solve.h) on the test binary's
// backend: symmetric and positive definite on compressed and inverted particles, and equal to the
// derivative of the explicit MLS force (a double-precision finite difference) where the stiffness
// needs no definiteness fix; and which velocity components walls and colliders hold.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/memory.h"
#include "kernels/material/lame.h"
#include "kernels/material/material.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/grid_boundary.h"
#include "kernels/mpm/implicit_solve.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "tests/kernels/svd/svd_test_matrices.h"
#include "tests/support/grid_vectors.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

using M = Mat3<double>;

constexpr float kDx = 1.0f / 32.0f;
constexpr int kCells = 32;
constexpr int kParticlesPerAxis = 8;  // 2 per cell: a block of 4 cells, 512 particles
constexpr float kDensity = 1000.0f;
constexpr double kYoung = 1e6, kPoisson = 0.3;

using test::dot;
using test::random_free_vector;
using test::with_host_block_keys;

// Fixed corotated and neo-Hookean particles side by side (alternating), so both the SVD models and
// the cofactor ones reach the operator through their principal-space stiffness.
std::vector<material::MaterialParams<double>> materials() {
  const material::Lame<double> lame = material::lame_from_young_poisson(kYoung, kPoisson);
  return {material::MaterialParams<double>::fixed_corotated(lame), material::MaterialParams<double>::neo_hookean(lame)};
}

// The operator of one substep over a lattice block whose particle p has deformation gradient F(p).
class ImplicitOperatorFixture {
 public:
  ImplicitOperatorFixture(const std::function<M(Index)>& deformation, float dt)
      : exec_(test::exec()),
        init_(lattice(deformation)),
        particles_(exec_.backend, init_),
        grid_(exec_.backend, kDx, false) {
    std::vector<material::MaterialParams<float>> table;
    for (const material::MaterialParams<double>& m : materials())
      table.push_back({m.model, float(m.mu), float(m.lambda), 0.0f, 0.0f, 0.0f});
    materials_ = DeviceBuffer<material::MaterialParams<float>>::from_host(exec_.backend, table);
    failures_ =
        DeviceBuffer<std::int64_t>::from_host(exec_.backend, std::vector<std::int64_t>(kStageCount, kNoFailure));

    StepParams& step = system_.step;
    step.dt = dt;
    for (int a = 0; a < 3; ++a) step.domain.cells[a] = kCells;
    step.domain.wall_cells = 2;  // far from the block: no wall holds a component
    step.materials = materials_.span();
    step.first_failure = failures_.span();

    const ParticleView particles = particles_.view();
    grid_.rebuild(exec_, Vec3Planes<const float>(particles.x));
    const GridView grid = grid_.view();
    particle_to_grid(exec_, particles, grid, step);  // the node masses M
    nodes_ = grid.blocks * kNodesPerBlock;
    stiffness_ = DeviceBuffer<material::PrincipalStiffness<float>>(exec_.backend, particles.count);
    projector_ = DeviceBuffer<float>(exec_.backend, 9 * nodes_);
    linearise_particles(exec_, particles, step, stiffness_.span());
    find_projectors(exec_, grid, DomainView{}, step, Mat3Planes<float>(projector_.data(), nodes_));
    system_.particles = particles;
    system_.grid = grid;
    system_.stiffness = stiffness_.span();
    system_.projector = Mat3Planes<const float>(projector_.data(), nodes_);
  }

  Index unknowns() const { return 3 * nodes_; }
  const mpm::ParticleInit& init() const { return init_; }
  // Per node and component, 1 where the velocity is unknown and 0 where held: the projectors'
  // diagonals, which here (no walls or colliders in reach) are the whole projectors.
  std::vector<float> free() const {
    const std::vector<float> S = projector_.to_host(exec_.stream);
    std::vector<float> diagonal(3 * nodes_);
    for (int a = 0; a < 3; ++a)
      std::copy(S.begin() + 4 * a * nodes_, S.begin() + (4 * a + 1) * nodes_, diagonal.begin() + a * nodes_);
    return diagonal;
  }
  float dt() const { return system_.step.dt; }

  // A x (with_stiffness) or M x, both masked by S.
  std::vector<float> apply(const std::vector<float>& x, bool with_stiffness) const {
    const DeviceBuffer<float> in = DeviceBuffer<float>::from_host(exec_.backend, x, exec_.stream);
    DeviceBuffer<float> out(exec_.backend, unknowns());
    if (with_stiffness)
      apply_implicit_operator(exec_, system_, in.span(), out.span());
    else
      apply_mass(exec_, system_, in.span(), out.span());
    return out.to_host(exec_.stream);
  }

  // Grid coordinates of every active node, in the operator's node order.
  std::vector<std::tuple<int, int, int>> node_coordinates() const {
    std::vector<std::uint64_t> keys;
    const GridView host_grid = with_host_block_keys(exec_, system_.grid, keys);
    std::vector<std::tuple<int, int, int>> coordinates;
    for (Index n = 0; n < nodes_; ++n) {
      const GridNode node(host_grid, n);
      coordinates.emplace_back(node.index[0], node.index[1], node.index[2]);
    }
    return coordinates;
  }

 private:
  static ParticleInit lattice(const std::function<M(Index)>& deformation) {
    const double h = kDx / 2.0, low = 0.4;
    const Index n = kParticlesPerAxis * kParticlesPerAxis * kParticlesPerAxis;
    ParticleInit init;
    init.x.resize(3 * n);
    init.v.assign(3 * n, 0.0f);
    init.F.resize(9 * n);
    for (Index p = 0; p < n; ++p) {
      const Index index[3] = {p / (kParticlesPerAxis * kParticlesPerAxis), p / kParticlesPerAxis % kParticlesPerAxis,
                              p % kParticlesPerAxis};
      for (int a = 0; a < 3; ++a) init.x[a * n + p] = float(low + (double(index[a]) + 0.5) * h);
      const M F = deformation(p);
      for (int k = 0; k < 9; ++k) init.F[k * n + p] = float(F(k / 3, k % 3));
      init.mass.push_back(float(kDensity * h * h * h));
      init.volume0.push_back(float(h * h * h));
      init.material.push_back(std::int32_t(p % 2));
      init.dirichlet_group.push_back(kNoDirichletGroup);
    }
    return init;
  }

  Exec exec_;
  ParticleInit init_;
  ParticleSet particles_;
  SparseGrid grid_;
  DeviceBuffer<material::MaterialParams<float>> materials_;
  DeviceBuffer<std::int64_t> failures_;
  DeviceBuffer<material::PrincipalStiffness<float>> stiffness_;
  DeviceBuffer<float> projector_;
  ImplicitSystem system_;
  Index nodes_ = 0;
};

// One F per particle: random frames and singular values σ_a uniform in [low_a, high_a].
std::vector<M> random_deformations(std::uint64_t seed, const Vec3<double>& low, const Vec3<double>& high) {
  test::MatrixSampler sampler(seed);
  std::vector<M> F;
  for (int p = 0; p < kParticlesPerAxis * kParticlesPerAxis * kParticlesPerAxis; ++p)
    F.push_back(sampler.with_singular_values(sampler.uniform(low[0], high[0]), sampler.uniform(low[1], high[1]),
                                             sampler.uniform(low[2], high[2])));
  return F;
}

TEST(ImplicitOperator, IsSymmetricAndPositiveDefiniteUnderCompressionAndInversion) {
  const std::vector<M> F = random_deformations(3, Vec3<double>(0.3, 0.1, -0.6), Vec3<double>(1.5, 1.0, 0.8));
  // Δt of ten elastic wave crossings of a cell: Δt² K dominates M, so definiteness rests on K.
  const double wave_speed = std::sqrt(kYoung * (1 - kPoisson) / ((1 + kPoisson) * (1 - 2 * kPoisson)) / kDensity);
  const ImplicitOperatorFixture fixture([&](Index p) { return F[p]; }, float(10 * kDx / wave_speed));
  const std::vector<float> free = fixture.free();
  std::mt19937_64 rng(17);
  double stiffness_share = 0.0;
  const int pairs = 10;
  for (int sample = 0; sample < pairs; ++sample) {
    const std::vector<float> u = random_free_vector(free, rng), w = random_free_vector(free, rng);
    const std::vector<float> Au = fixture.apply(u, true), Aw = fixture.apply(w, true), Mu = fixture.apply(u, false);
    // Float sums over ~10⁴ products of either sign: agreement to 1e-5 of the terms' magnitude.
    const double uAw = dot(u, Aw), wAu = dot(w, Au);
    EXPECT_NEAR(uAw, wAu, 1e-5 * std::sqrt(dot(u, u) * dot(Aw, Aw) + dot(w, w) * dot(Au, Au))) << "sample " << sample;
    const double uAu = dot(u, Au), uMu = dot(u, Mu);
    EXPECT_GT(uMu, 0.0);
    EXPECT_GE(uAu - uMu, -1e-5 * uAu) << "Δt² uᵀ K u < 0, sample " << sample;
    stiffness_share += (uAu - uMu) / uAu / pairs;
  }
  EXPECT_GT(stiffness_share, 0.9);  // the test is about K, not about M
}

// f_i(s) = −Σ_p V⁰_p P(F̂_p) F_pᵀ ∇w_ip with F̂_p = (I + s Δt Σ_j δv_j ∇w_jpᵀ) F_p: the explicit MLS
// force when the grid has moved by s Δt δv, in double. Δt² K δv = −Δt df/ds at s = 0.
std::vector<double> explicit_force(const ParticleInit& init,
                                   const std::map<std::tuple<int, int, int>, Index>& node_index, Index nodes,
                                   const std::vector<float>& dv, double s, double dt) {
  const std::vector<material::MaterialParams<double>> table = materials();
  const double d_inverse = double(kInverseInertiaScale) / (double(kDx) * kDx);
  const Index n = init.count();
  std::vector<double> force(3 * nodes, 0.0);
  for (Index p = 0; p < n; ++p) {
    const Vec3<double> x(init.x[p], init.x[n + p], init.x[2 * n + p]);
    M F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = init.F[k * n + p];
    const QuadraticStencil<double> stencil(x, 1.0 / kDx);
    std::vector<std::pair<Index, Vec3<double>>> gradients;  // node, ∇w
    M displacement_gradient = M::zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          const Index node = node_index.at({stencil.base[0] + i, stencil.base[1] + j, stencil.base[2] + k});
          const Vec3<double> gradient = (stencil.weight(i, j, k) * d_inverse) * stencil.offset(i, j, k, kDx);
          const Vec3<double> v(dv[node], dv[nodes + node], dv[2 * nodes + node]);
          displacement_gradient += M::outer(v, gradient);
          gradients.emplace_back(node, gradient);
        }
    const M F_moved = (M::identity() + (s * dt) * displacement_gradient) * F;
    const M moment =
        double(init.volume0[p]) * times_transpose(material::first_piola(table[init.material[p]], F_moved), F);
    for (const auto& [node, gradient] : gradients) {
      const Vec3<double> f = moment * gradient;
      for (int a = 0; a < 3; ++a) force[a * nodes + node] -= f[a];
    }
  }
  return force;
}

TEST(ImplicitOperator, IsTheDerivativeOfTheExplicitForceWhereTheStiffnessIsDefinite) {
  // Stretches up to 10% in random frames: both models' stiffness is semidefinite there.
  const std::vector<M> F = random_deformations(5, Vec3<double>::constant(1.0), Vec3<double>::constant(1.1));
  test::MatrixSampler sampler(7);
  const std::vector<material::MaterialParams<double>> table = materials();
  for (std::size_t p = 0; p < F.size(); ++p) {
    const M dF = sampler.gaussian();
    const material::MaterialParams<double>& params = table[p % 2];
    ASSERT_LE(frobenius_norm(material::definite_stiffness(params, F[p]).apply(dF) -
                             material::first_piola_differential(params, F[p], dF)),
              1e-9 * frobenius_norm(material::first_piola_differential(params, F[p], dF)))
        << "the premise: no definiteness fix at particle " << p;
  }
  const ImplicitOperatorFixture fixture([&](Index p) { return F[p]; }, 1e-3f);
  const std::vector<std::tuple<int, int, int>> coordinates = fixture.node_coordinates();
  std::map<std::tuple<int, int, int>, Index> node_index;
  for (std::size_t n = 0; n < coordinates.size(); ++n) node_index[coordinates[n]] = Index(n);
  const Index nodes = Index(coordinates.size());

  std::mt19937_64 rng(23);
  const std::vector<float> free = fixture.free();
  const std::vector<float> dv = random_free_vector(free, rng);
  const std::vector<float> A_dv = fixture.apply(dv, true), M_dv = fixture.apply(dv, false);
  // Central differences: ‖s Δt ∇δv‖ ≈ 1e-6, so truncation (s²) and rounding (1e-16 / s) both stay
  // near 1e-10 relative, far below the float operator's error.
  const double s = 1e-5, dt = fixture.dt();
  const std::vector<double> forward = explicit_force(fixture.init(), node_index, nodes, dv, s, dt);
  const std::vector<double> backward = explicit_force(fixture.init(), node_index, nodes, dv, -s, dt);
  double error = 0.0, scale = 0.0;
  for (Index k = 0; k < 3 * nodes; ++k) {
    const double expected = free[k] * -dt * (forward[k] - backward[k]) / (2 * s);
    const double actual = double(A_dv[k]) - double(M_dv[k]);
    error += (actual - expected) * (actual - expected);
    scale += expected * expected;
  }
  // The float operator: SVDs accurate to ~1e-6 of σ₀ and sums of 27 particles' terms per node
  // (measured 7e-7).
  EXPECT_LE(std::sqrt(error / scale), 1e-5);
}

// A row of particles 2.2 cells above the floor (their stencils reach node rows y = 1, 2, 3; rows
// y < 3 are wall nodes) and one particle around a node inside a small slip sphere, whose normal
// there is oblique. The nodes get mass 1 except in the layer z = 18 (massless), and
// v* = (0.3, 0 or 0.5, -0.2): at the floor, the nodes with an odd x index move away from it.
TEST(ImplicitUnknowns, WallsAndCollidersHoldTheDirectionsTheyFix) {
  const Exec& exec = test::exec();
  std::vector<Vec3<float>> positions;
  for (int i = 0; i < 8; ++i) positions.emplace_back((10.5f + i) * kDx, 2.2f * kDx, 16.5f * kDx);
  positions.emplace_back(24.5f * kDx, 16.5f * kDx, 16.5f * kDx);
  const Index count = Index(positions.size());
  std::vector<float> planes(3 * count);
  for (Index p = 0; p < count; ++p)
    for (int a = 0; a < 3; ++a) planes[a * count + p] = positions[p][a];
  const DeviceBuffer<float> x = DeviceBuffer<float>::from_host(exec.backend, planes, exec.stream);
  SparseGrid sparse_grid(exec.backend, kDx, false);
  sparse_grid.rebuild(exec, Vec3Planes<const float>(x.data(), count));
  const GridView grid = sparse_grid.view();
  const Index nodes = grid.blocks * kNodesPerBlock;

  std::vector<std::uint64_t> keys;
  const GridView host_grid = with_host_block_keys(exec, grid, keys);
  std::vector<float> mass(nodes), velocity(3 * nodes);
  for (Index n = 0; n < nodes; ++n) {
    const GridNode node(host_grid, n);
    mass[n] = node.index[2] == 18 ? 0.0f : 1.0f;
    velocity[n] = 0.3f;
    velocity[nodes + n] = node.index[0] % 2 ? 0.5f : 0.0f;
    velocity[2 * nodes + n] = -0.2f;
  }
  memory::copy(grid.mass.data(), exec.backend, mass.data(), Backend::Cpu, nodes * sizeof(float), exec.stream);
  for (int a = 0; a < 3; ++a)
    memory::copy(grid.velocity.data() + a * grid.velocity.count(), exec.backend, velocity.data() + a * nodes,
                 Backend::Cpu, nodes * sizeof(float), exec.stream);

  ColliderState sphere;
  sphere.shape = ColliderShape::Sphere;
  // Around node (25, 17, 17) and none of its neighbours, off its centre: the node's normal is oblique.
  const Vec3<float> inside_node(25.0f * kDx, 17.0f * kDx, 17.0f * kDx);
  sphere.center = Vec3<float>(25.2f * kDx, 17.1f * kDx, 16.9f * kDx);
  sphere.half_extents = Vec3<float>::constant(0.6f * kDx);
  sphere.contact = ContactType::Slip;
  const Vec3<float> normal = (1.0f / norm(inside_node - sphere.center)) * (inside_node - sphere.center);
  const DeviceBuffer<ColliderState> colliders =
      DeviceBuffer<ColliderState>::from_host(exec.backend, std::vector<ColliderState>{sphere}, exec.stream);
  for (const ContactType contact : {ContactType::Separate, ContactType::Sticky}) {
    StepParams step;
    for (int a = 0; a < 3; ++a) step.domain.cells[a] = kCells;
    step.domain.wall_cells = 3;
    step.domain.wall_contact = contact;
    step.colliders = colliders.span();
    DeviceBuffer<float> projector(exec.backend, 9 * nodes);
    find_projectors(exec, grid, DomainView{}, step, Mat3Planes<float>(projector.data(), nodes));
    const std::vector<float> planes = projector.to_host(exec.stream);
    const Mat3Planes<const float> actual(planes.data(), nodes);
    int wall_nodes = 0, separating = 0, inside = 0;
    for (Index n = 0; n < nodes; ++n) {
      const GridNode node(host_grid, n);
      Mat3<float> expected = Mat3<float>::identity();
      if (node.index[1] < 3) {
        ++wall_nodes;
        separating += node.index[0] % 2;
        expected = contact == ContactType::Sticky ? Mat3<float>::zero()
                                                  : Mat3<float>::diag(1.0f, node.index[0] % 2 ? 1.0f : 0.0f, 1.0f);
      }
      if (node.index[0] == 25 && node.index[1] == 17 && node.index[2] == 17) {
        ++inside;
        expected = Mat3<float>::identity() - Mat3<float>::outer(normal, normal);  // the slip sphere holds n only
      }
      if (mass[n] == 0.0f) expected = Mat3<float>::zero();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(actual.load(n)(r, c), expected(r, c), 1e-6f)
              << "node (" << node.index[0] << ", " << node.index[1] << ", " << node.index[2] << ") entry " << r << c;
    }
    EXPECT_GT(wall_nodes, 0);
    EXPECT_GT(separating, 0);
    EXPECT_EQ(inside, 1);
  }
}

}  // namespace
}  // namespace romp::mpm
