// The implicit step's operator over particle domains (kernels/mpm/implicit_solve.h), with and without
// enriched corners among its unknowns: symmetric and semidefinite in K, its Jacobi diagonal equal to
// the operator's own diagonal entry by entry, and equal to the derivative of the explicit corner
// forces (a double-precision finite difference) where the stiffness needs no definiteness fix.
// Runs on the binary's backend.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/memory.h"
#include "kernels/material/lame.h"
#include "kernels/material/material.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/grid_boundary.h"
#include "kernels/mpm/implicit_solve.h"
#include "kernels/mpm/particle_domains.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/sparse_grid.h"
#include "tests/host/mpm_test_scenes.h"
#include "tests/kernels/svd/svd_test_matrices.h"
#include "tests/support/grid_vectors.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

using M = Mat3<double>;

constexpr float kDx = 1.0f / 32.0f;
constexpr int kCells = 32;
constexpr float kDensity = 1000.0f;
const material::Lame<double> kLame = material::lame_from_young_poisson(1e6, 0.3);

// A cube of 4 cells, 2 particles per cell and axis, each with its lattice cell as its domain (512
// domains, 729 shared corners), far from the walls. Particle p has deformation gradient F[p]; the
// corners sit up to 5% of a domain's edge off the lattice (the operator is linear in the unknowns
// at any state); with `enrich`, the corners of every third particle are enriched, so that some
// particles are transitional and some corners are shared by enriched and grid-bound particles.
class DomainOperatorFixture {
 public:
  DomainOperatorFixture(const std::vector<M>& F, float dt, bool enrich)
      : exec_(test::exec()),
        init_(body(F)),
        particles_(exec_.backend, init_),
        domains_(exec_.backend, init_.domains),
        grid_(exec_.backend, kDx, true) {
    const material::MaterialParams<float> params =
        material::MaterialParams<float>::fixed_corotated(material::Lame<float>{float(kLame.mu), float(kLame.lambda)});
    materials_ = DeviceBuffer<material::MaterialParams<float>>::from_host(
        exec_.backend, std::vector<material::MaterialParams<float>>{params});
    failures_ =
        DeviceBuffer<std::int64_t>::from_host(exec_.backend, std::vector<std::int64_t>(kStageCount, kNoFailure));
    StepParams& step = system_.step;
    step.dt = dt;
    for (int a = 0; a < 3; ++a) step.domain.cells[a] = kCells;
    step.domain.wall_cells = 2;
    step.materials = materials_.span();
    step.first_failure = failures_.span();

    const ParticleView particles = particles_.view();
    const DomainView domains = domains_.view();
    enriched_.assign(std::size_t(domains.corners), 0);
    if (enrich)
      for (Index p = 0; p < init_.count(); p += 3)
        for (int a = 0; a < kDomainCorners; ++a) {
          const std::size_t entry = std::size_t(kDomainCorners * init_.domain[std::size_t(p)] + a);
          enriched_[std::size_t(init_.domains.corner[entry])] = 1;
        }
    memory::copy(domains.enriched.data(), exec_.backend, enriched_.data(), Backend::Cpu,
                 enriched_.size() * sizeof(std::int32_t), exec_.stream);
    grid_.rebuild(exec_, Vec3Planes<const float>(particles.x), Vec3Planes<const float>(domains.x));
    const GridView grid = grid_.view();
    particles_to_corners(exec_, particles, domains, step);  // corner masses
    corners_to_grid(exec_, domains, grid, step);            // node masses, enriched corners' v*
    nodes_ = grid.blocks * kNodesPerBlock;
    const Index entries = nodes_ + domains.corners;
    stiffness_ = DeviceBuffer<material::PrincipalStiffness<float>>(exec_.backend, particles.count);
    projector_ = DeviceBuffer<float>(exec_.backend, 9 * entries);
    corner_scratch_ = DeviceBuffer<float>(exec_.backend, 6 * domains.corners);
    linearise_particles(exec_, particles, step, stiffness_.span());
    find_projectors(exec_, grid, domains, step, Mat3Planes<float>(projector_.data(), entries));
    system_.particles = particles;
    system_.grid = grid;
    system_.stiffness = stiffness_.span();
    system_.projector = Mat3Planes<const float>(projector_.data(), entries);
    system_.domains = domains;
    system_.corner_displacement = Vec3Planes<float>(corner_scratch_.data(), domains.corners);
    system_.corner_force = Vec3Planes<float>(corner_scratch_.data() + 3 * domains.corners, domains.corners);
  }

  Index nodes() const { return nodes_; }
  Index entries() const { return system_.entries(); }
  float dt() const { return system_.step.dt; }
  const ParticleInit& init() const { return init_; }
  bool enriched(Index corner) const { return enriched_[std::size_t(corner)] != 0; }

  // 1 where a component is unknown, 0 where held: the projectors' diagonals, which here (no walls
  // or colliders in reach) are the whole projectors.
  std::vector<float> free() const {
    const std::vector<float> S = projector_.to_host(exec_.stream);
    const Index n = entries();
    std::vector<float> diagonal(3 * n);
    for (int a = 0; a < 3; ++a) std::copy(S.begin() + 4 * a * n, S.begin() + (4 * a + 1) * n, diagonal.begin() + a * n);
    return diagonal;
  }

  // A x (with_stiffness) or M x, both masked by S.
  std::vector<float> apply(const std::vector<float>& x, bool with_stiffness) const {
    const DeviceBuffer<float> in = DeviceBuffer<float>::from_host(exec_.backend, x, exec_.stream);
    DeviceBuffer<float> out(exec_.backend, 3 * entries());
    if (with_stiffness)
      apply_implicit_operator(exec_, system_, in.span(), out.span());
    else
      apply_mass(exec_, system_, in.span(), out.span());
    return out.to_host(exec_.stream);
  }

  std::vector<float> inverse_diagonal() const {
    DeviceBuffer<float> out(exec_.backend, 3 * entries());
    jacobi_inverse_diagonal(exec_, system_, out.span());
    return out.to_host(exec_.stream);
  }

  // The index of each active node by its grid coordinates.
  std::map<std::tuple<int, int, int>, Index> node_index() const {
    std::vector<std::uint64_t> keys;
    const GridView host_grid = test::with_host_block_keys(exec_, system_.grid, keys);
    std::map<std::tuple<int, int, int>, Index> index;
    for (Index n = 0; n < nodes_; ++n) {
      const GridNode node(host_grid, n);
      index[{node.index[0], node.index[1], node.index[2]}] = n;
    }
    return index;
  }

 private:
  static ParticleInit body(const std::vector<M>& F) {
    ParticleInit init = test::lattice_box_with_domains(Vec3<float>::constant(0.4375f), Vec3<float>::constant(0.5625f),
                                                       kDx, 2, kDensity);
    const Index n = init.count();
    EXPECT_EQ(std::size_t(n), F.size());
    init.F.resize(std::size_t(9 * n));
    for (Index p = 0; p < n; ++p)
      for (int k = 0; k < 9; ++k) init.F[std::size_t(k * n + p)] = float(F[std::size_t(p)](k / 3, k % 3));
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<float> offset(-0.05f * 0.5f * kDx, 0.05f * 0.5f * kDx);
    for (float& coordinate : init.domains.corner_x) coordinate += offset(rng);
    return init;
  }

  Exec exec_;
  ParticleInit init_;
  ParticleSet particles_;
  ParticleDomains domains_;
  SparseGrid grid_;
  std::vector<std::int32_t> enriched_;
  DeviceBuffer<material::MaterialParams<float>> materials_;
  DeviceBuffer<std::int64_t> failures_;
  DeviceBuffer<material::PrincipalStiffness<float>> stiffness_;
  DeviceBuffer<float> projector_, corner_scratch_;
  ImplicitSystem system_;
  Index nodes_ = 0;
};

constexpr Index kParticles = 512;

// One F per particle: random frames, singular values uniform in [low, high].
std::vector<M> random_deformations(std::uint64_t seed, double low, double high) {
  test::MatrixSampler sampler(seed);
  std::vector<M> F;
  for (Index p = 0; p < kParticles; ++p)
    F.push_back(sampler.with_singular_values(sampler.uniform(low, high), sampler.uniform(low, high),
                                             sampler.uniform(low, high)));
  return F;
}

// Δt of ten elastic wave crossings of a cell: Δt² K dominates M.
float long_step() {
  const double wave_speed = std::sqrt((kLame.lambda + 2.0 * kLame.mu) / kDensity);
  return float(10.0 * kDx / wave_speed);
}

class ImplicitDomainOperator : public ::testing::TestWithParam<bool> {};  // with enriched corners or not
INSTANTIATE_TEST_SUITE_P(Enrichment, ImplicitDomainOperator, ::testing::Bool());

TEST_P(ImplicitDomainOperator, IsSymmetricAndSemidefinite) {
  // Compressed, stretched and inverted domains: the definiteness fix is what keeps K semidefinite.
  test::MatrixSampler sampler(3);
  std::vector<M> F;
  for (Index p = 0; p < kParticles; ++p)
    F.push_back(
        sampler.with_singular_values(sampler.uniform(0.3, 1.5), sampler.uniform(0.1, 1.0), sampler.uniform(-0.6, 0.8)));
  const DomainOperatorFixture fixture(F, long_step(), GetParam());
  const std::vector<float> free = fixture.free();
  Index free_corner_components = 0;
  for (int a = 0; a < 3; ++a)
    for (Index n = fixture.nodes(); n < fixture.entries(); ++n)
      free_corner_components += free[a * fixture.entries() + n] > 0;
  if (GetParam())
    EXPECT_GT(free_corner_components, 0) << "no enriched corner is an unknown";
  else
    EXPECT_EQ(free_corner_components, 0) << "a corner bound to the grid is an unknown";

  std::mt19937_64 rng(17);
  double stiffness_share = 0.0;
  const int pairs = 10;
  for (int sample = 0; sample < pairs; ++sample) {
    const std::vector<float> u = test::random_free_vector(free, rng), w = test::random_free_vector(free, rng);
    const std::vector<float> Au = fixture.apply(u, true), Aw = fixture.apply(w, true), Mu = fixture.apply(u, false);
    const double uAw = test::dot(u, Aw), wAu = test::dot(w, Au);
    EXPECT_NEAR(uAw, wAu, 1e-5 * std::sqrt(test::dot(u, u) * test::dot(Aw, Aw) + test::dot(w, w) * test::dot(Au, Au)))
        << "sample " << sample;
    const double uAu = test::dot(u, Au), uMu = test::dot(u, Mu);
    EXPECT_GT(uMu, 0.0);
    EXPECT_GE(uAu - uMu, -1e-5 * uAu) << "Δt² uᵀ K u < 0, sample " << sample;
    stiffness_share += (uAu - uMu) / uAu / pairs;
  }
  EXPECT_GT(stiffness_share, 0.9);
}

TEST_P(ImplicitDomainOperator, JacobiDiagonalIsTheOperatorsDiagonal) {
  const DomainOperatorFixture fixture(random_deformations(5, 0.7, 1.3), long_step(), GetParam());
  const std::vector<float> free = fixture.free(), inverse_diagonal = fixture.inverse_diagonal();
  // Every 3rd free corner component and every 7th free node component: e_kᵀ A e_k against 1 / D⁻¹_kk.
  std::vector<Index> checked;
  for (Index k = 0; k < Index(free.size()); ++k) {
    const bool corner = k % fixture.entries() >= fixture.nodes();
    if (free[k] > 0 && k % (corner ? 3 : 7) == 0) checked.push_back(k);
  }
  ASSERT_GT(checked.size(), 50u);
  for (const Index k : checked) {
    std::vector<float> e(free.size(), 0.0f);
    e[k] = 1.0f;
    const double diagonal = fixture.apply(e, true)[k];
    ASSERT_GT(inverse_diagonal[k], 0.0f) << "entry " << k;
    EXPECT_NEAR(1.0 / inverse_diagonal[k], diagonal, 1e-5 * diagonal)
        << "entry " << k << (k % fixture.entries() >= fixture.nodes() ? " (a corner)" : " (a node)");
  }
}

// f(s): the explicit force on every unknown when the unknowns have moved by s Δt δv, in double.
// A corner moves by its own entry when enriched, by the grid's interpolated motion otherwise; each
// domain particle's F moves in the reference configuration (F + Σ_α u_α g_αᵀ) and its corner forces
// −V⁰ P g_α stay at enriched corners and reach the grid from the others with the corners' weights.
std::vector<double> explicit_force(const DomainOperatorFixture& fixture,
                                   const std::map<std::tuple<int, int, int>, Index>& node_index,
                                   const std::vector<float>& dv, double s) {
  const ParticleInit& init = fixture.init();
  const DomainInit& domains = init.domains;
  const Index nodes = fixture.nodes(), entries = fixture.entries(), corners = domains.corner_count();
  const double dt = fixture.dt();
  const material::MaterialParams<double> params = material::MaterialParams<double>::fixed_corotated(kLame);
  auto stencil_of = [&](Index c) {
    const Vec3<double> x(domains.corner_x[std::size_t(c)], domains.corner_x[std::size_t(corners + c)],
                         domains.corner_x[std::size_t(2 * corners + c)]);
    return QuadraticStencil<double>(x, 1.0 / double(kDx));
  };
  auto node_of = [&](const QuadraticStencil<double>& stencil, int i, int j, int k) {
    return node_index.at({stencil.base[0] + i, stencil.base[1] + j, stencil.base[2] + k});
  };
  std::vector<Vec3<double>> u(std::size_t(corners), Vec3<double>::zero());
  for (Index c = 0; c < corners; ++c) {
    if (fixture.enriched(c)) {
      for (int a = 0; a < 3; ++a) u[std::size_t(c)][a] = dv[std::size_t(a * entries + nodes + c)];
    } else {
      const QuadraticStencil<double> stencil = stencil_of(c);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a)
              u[std::size_t(c)][a] +=
                  stencil.weight(i, j, k) * dv[std::size_t(a * entries + node_of(stencil, i, j, k))];
    }
    u[std::size_t(c)] = (s * dt) * u[std::size_t(c)];
  }
  std::vector<Vec3<double>> corner_force(std::size_t(corners), Vec3<double>::zero());
  const Index n = init.count();
  for (Index p = 0; p < n; ++p) {
    const Index d = init.domain[std::size_t(p)];
    M F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = init.F[std::size_t(k * n + p)];
    auto gradient = [&](int alpha) {
      const std::size_t e = std::size_t(kDomainCorners * d + alpha);
      return Vec3<double>(domains.gradient[3 * e], domains.gradient[3 * e + 1], domains.gradient[3 * e + 2]);
    };
    for (int alpha = 0; alpha < kDomainCorners; ++alpha)
      F += M::outer(u[std::size_t(domains.corner[std::size_t(kDomainCorners * d + alpha)])], gradient(alpha));
    const M stress = double(init.volume0[std::size_t(p)]) * material::first_piola(params, F);
    for (int alpha = 0; alpha < kDomainCorners; ++alpha)
      corner_force[std::size_t(domains.corner[std::size_t(kDomainCorners * d + alpha)])] -= stress * gradient(alpha);
  }
  std::vector<double> force(std::size_t(3 * entries), 0.0);
  for (Index c = 0; c < corners; ++c) {
    if (fixture.enriched(c)) {
      for (int a = 0; a < 3; ++a) force[std::size_t(a * entries + nodes + c)] += corner_force[std::size_t(c)][a];
      continue;
    }
    const QuadraticStencil<double> stencil = stencil_of(c);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          for (int a = 0; a < 3; ++a)
            force[std::size_t(a * entries + node_of(stencil, i, j, k))] +=
                stencil.weight(i, j, k) * corner_force[std::size_t(c)][a];
  }
  return force;
}

TEST_P(ImplicitDomainOperator, IsTheDerivativeOfTheExplicitCornerForces) {
  // Stretches up to 10%: fixed corotated's stiffness is semidefinite there, so no fix applies.
  const DomainOperatorFixture fixture(random_deformations(7, 1.0, 1.1), 1e-3f, GetParam());
  const std::map<std::tuple<int, int, int>, Index> node_index = fixture.node_index();
  std::mt19937_64 rng(23);
  const std::vector<float> free = fixture.free();
  const std::vector<float> dv = test::random_free_vector(free, rng);
  const std::vector<float> A_dv = fixture.apply(dv, true), M_dv = fixture.apply(dv, false);
  const double s = 1e-5, dt = fixture.dt();
  const std::vector<double> forward = explicit_force(fixture, node_index, dv, s);
  const std::vector<double> backward = explicit_force(fixture, node_index, dv, -s);
  double error = 0.0, scale = 0.0, corner_scale = 0.0;
  for (std::size_t k = 0; k < free.size(); ++k) {
    const double expected = free[k] * -dt * (forward[k] - backward[k]) / (2 * s);
    const double actual = double(A_dv[k]) - double(M_dv[k]);
    error += (actual - expected) * (actual - expected);
    scale += expected * expected;
    if (Index(k) % fixture.entries() >= fixture.nodes()) corner_scale += expected * expected;
  }
  if (GetParam()) EXPECT_GT(corner_scale, 1e-3 * scale) << "the enriched corners carry no force";
  EXPECT_LE(std::sqrt(error / scale), 1e-5);
}

}  // namespace
}  // namespace romp::mpm
