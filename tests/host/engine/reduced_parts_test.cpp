// The reduced step's parts alone, on both backends: the sample set (hyper-reduction's draws, decoded
// kinematics), the projections of the latent state and the Lagrangian quadrature, under the translation
// map g(X; x̂) = X + x̂ whose every answer is known in closed form; the domain quadrature against the
// full-order step on particle domains.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "host/engine/deformation_map.h"
#include "host/engine/full_order_sim.h"
#include "host/engine/latent_projection.h"
#include "host/engine/quadrature_points.h"
#include "host/engine/reduced_quadrature.h"
#include "host/engine/sample_set.h"
#include "host/engine/step_inputs.h"
#include "host/scene/material_library.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"
#include "tests/host/mpm_test_scenes.h"
#include "tests/host/rom_test_maps.h"
#include "tests/support/test_exec.h"

namespace romp::engine {
namespace {

// 4³ lattice points of a 1 cm cube at 0.5 m; the first 16 in Dirichlet group 0.
mpm::ParticleInit body() {
  mpm::ParticleInit init =
      test::lattice_box(Vec3<float>::constant(0.49f), Vec3<float>::constant(0.51f), 0.01f, 2, 1000.0f);
  for (std::size_t p = 0; p < 16; ++p) init.dirichlet_group[p] = 0;
  return init;
}

std::vector<float> host(const Exec& exec, const DeviceBuffer<float>& buffer, Index count) {
  std::vector<float> values = buffer.to_host(exec.stream);
  values.resize(std::size_t(count));
  return values;
}

TEST(SampleSet, DrawsDistinctSortedSamplesWithEveryBoundarysShare) {
  const mpm::ParticleInit init = body();
  ASSERT_EQ(init.count(), 64);
  const ReferenceBody reference(test::exec().backend, init);
  SampleSet samples(init, /*dirichlet_groups=*/1, /*wanted=*/10, /*boundary_samples=*/5, /*seed=*/3, /*latent=*/3);
  // The 20 substeps' samples come from one upload, and each substep takes a row of its own.
  EXPECT_GE(samples.rows_ahead(), 20);
  std::set<std::vector<std::int32_t>> rows;
  for (int draw = 0; draw < 20; ++draw) {
    samples.draw(test::exec(), reference);
    ASSERT_EQ(samples.count(), 15);
    const std::vector<std::int32_t> index = download(test::exec().backend, samples.index(), test::exec().stream);
    EXPECT_TRUE(std::is_sorted(index.begin(), index.end()));
    EXPECT_EQ(std::set<std::int32_t>(index.begin(), index.end()).size(), index.size());
    EXPECT_EQ(std::count_if(index.begin(), index.end(), [](std::int32_t p) { return p < 16; }), 5);
    rows.insert(index);
    // The reference state gathered is the drawn points'.
    const std::vector<float> mass = host(test::exec(), samples.points().mass, 15);
    for (std::size_t i = 0; i < index.size(); ++i) EXPECT_EQ(mass[i], init.mass[std::size_t(index[i])]);
  }
  EXPECT_GE(rows.size(), 18u);
  // Every point once asked for none or all.
  SampleSet all(init, 1, 0, 5, 3, 3);
  all.draw(test::exec(), reference);
  EXPECT_EQ(all.count(), 64);
}

// A frame's samples go up before it, in one upload, whatever rows are left: its draws upload nothing, and
// the samples are the ones drawn a substep at a time.
TEST(SampleSet, DrawsAheadForAFrameInOneUploadAndTheSameSequence) {
  const mpm::ParticleInit init = body();
  const ReferenceBody reference(test::exec().backend, init);
  SampleSet one_by_one(init, 1, 10, 5, 3, 3), by_frames(init, 1, 10, 5, 3, 3);
  const Index rows = one_by_one.rows_ahead();
  auto sample_rows = [&reference](SampleSet& samples, Index draws) {
    std::vector<std::vector<std::int32_t>> drawn;
    for (Index d = 0; d < draws; ++d) {
      samples.draw(test::exec(), reference);
      drawn.push_back(download(test::exec().backend, samples.index(), test::exec().stream));
    }
    return drawn;
  };
  // One by one: an upload every rows_ahead() draws, 2 in rows + 10.
  const memory::Traffic start = memory::traffic();
  const auto expected = sample_rows(one_by_one, rows + 10);
  EXPECT_EQ(memory::traffic().uploads - start.uploads, 2);
  // By frames of rows − 5 and 15 draws: the second frame finds 5 rows left and uploads them with new ones first.
  std::vector<std::vector<std::int32_t>> got;
  for (const Index frame : {rows - 5, Index(15)}) {
    by_frames.draw_ahead(test::exec(), frame);
    const memory::Traffic before = memory::traffic();
    const auto drawn = sample_rows(by_frames, frame);
    EXPECT_EQ(memory::traffic().uploads - before.uploads, 0) << frame;
    got.insert(got.end(), drawn.begin(), drawn.end());
  }
  EXPECT_EQ(got, expected);
  // Enough rows left: no upload.
  const memory::Traffic before = memory::traffic();
  by_frames.draw_ahead(test::exec(), 3);
  EXPECT_EQ(memory::traffic().uploads - before.uploads, 0);
}

TEST(SampleSet, DecodesPositionsAndVelocitiesThroughTheMap) {
  const mpm::ParticleInit init = body();
  const ReferenceBody reference(test::exec().backend, init);
  const DeformationMap map(test::exec().backend, test::translation_map());
  SampleSet samples(init, 1, 0, 5, 3, 3);
  samples.draw(test::exec(), reference);
  const DeviceBuffer<float> latent = DeviceBuffer<float>::from_host(test::exec().backend, {0.1f, -0.2f, 0.3f, 1, 2, 3});
  samples.decode(test::exec(), map, latent.span().subspan(0, 3), latent.span().subspan(3, 3));
  const std::vector<float> x = samples.points().x.to_host(), v = samples.points().v.to_host();
  const Index n = init.count();
  for (Index p = 0; p < n; p += 9)
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(x[std::size_t(a * n + p)],
                  init.x[std::size_t(a * n + p)] + 0.1f * float(a == 0) - 0.2f * float(a == 1) + 0.3f * float(a == 2),
                  1e-6f);
      EXPECT_FLOAT_EQ(v[std::size_t(a * n + p)], float(a + 1));
    }
}

TEST(LatentProjection, FitsAndProjectsVelocitiesAndAdvancesThePosition) {
  const mpm::ParticleInit init = body();
  const Index n = init.count();
  const ReferenceBody reference(test::exec().backend, init);
  const DeformationMap map(test::exec().backend, test::translation_map());
  LatentProjection latent(test::exec().backend, {0.0f, 0.0f, 0.0f}, /*positions=*/false, {});
  SampleSet samples(init, 1, 0, 5, 3, 3);
  samples.draw(test::exec(), reference);
  samples.decode(test::exec(), map, latent.xhat(), latent.vhat());
  // Under a translation ∂g/∂x̂ = I: the fit of a uniform velocity is that velocity.
  std::vector<float> v(std::size_t(3 * n));
  for (Index p = 0; p < n; ++p)
    v[std::size_t(p)] = 0.5f, v[std::size_t(n + p)] = -1.0f, v[std::size_t(2 * n + p)] = 0.25f;
  const DeviceBuffer<float> velocities = DeviceBuffer<float>::from_host(test::exec().backend, v);
  const std::vector<float> fit =
      latent.fit_velocity(test::exec(), samples.dg_dxhat(), Vec3Planes<const float>(velocities.data(), n));
  ASSERT_EQ(fit.size(), 3u);
  EXPECT_NEAR(fit[0], 0.5f, 1e-6f);
  EXPECT_NEAR(fit[1], -1.0f, 1e-6f);
  EXPECT_NEAR(fit[2], 0.25f, 1e-6f);
  // The projection of the samples' velocities (their mean, here) and x̂ += Δt v̂.
  samples.decode(test::exec(), map, latent.xhat(), latent.vhat());
  latent.project(test::exec(), map, samples, 0.1f);
  const std::vector<float> state = download(test::exec().backend, latent.state());  // [x̂ | v̂ | status] of r = 3
  EXPECT_EQ(state[6], rom::kLatentSolved);
  EXPECT_NEAR(state[0], 0.05f, 1e-6f);
  EXPECT_NEAR(state[4], -1.0f, 1e-6f);
}

TEST(LagrangianQuadrature, EveryPointOrTheSamplesNeighboursAtTheirDecodedPlaces) {
  const mpm::ParticleInit init = body();
  const Index n = init.count();
  const ReferenceBody reference(test::exec().backend, init);
  const DeformationMap map(test::exec().backend, test::translation_map());
  const DeviceBuffer<float> latent = DeviceBuffer<float>::from_host(test::exec().backend, {0.01f, 0.0f, 0.0f, 0, 0, 0});
  const Span<const float> xhat = latent.span().subspan(0, 3), vhat = latent.span().subspan(3, 3);
  SampleSet samples(init, 1, 2, 0, 5, 3);
  samples.draw(test::exec(), reference);
  samples.decode(test::exec(), map, xhat, vhat);
  LagrangianQuadrature every(test::exec(), reference, 3, 0.01f, /*search=*/false);
  const mpm::ParticleView all = every.build(test::exec(), map, samples, xhat, vhat);
  EXPECT_EQ(all.count, n);
  EXPECT_EQ(every.failure_source().particle.size(), 0);  // point i is material point i
  const Vec3Planes<float> positions = every.material_positions();
  ASSERT_EQ(positions.count(), n);
  const std::vector<float> x = download(test::exec().backend, Span<const float>(positions.data(), 3 * n));
  EXPECT_NEAR(x[0], init.x[0] + 0.01f, 1e-6f);
  // Two samples in a 4³ body at dx = 1 cm: their stencils' reach covers the whole body.
  LagrangianQuadrature near(test::exec(), reference, 3, 0.01f, /*search=*/true);
  EXPECT_EQ(near.last_count(test::exec()), 0);                             // no build yet
  EXPECT_EQ(near.build(test::exec(), map, samples, xhat, vhat).count, n);  // a bound on the neighbours: every point
  EXPECT_EQ(download(test::exec().backend, near.live_count())[0], n);
  EXPECT_EQ(near.last_count(test::exec()), n);
  EXPECT_EQ(near.failure_source().particle.size(), n);
  EXPECT_EQ(near.points_so_far(test::exec()), n);
  near.build(test::exec(), map, samples, xhat, vhat);
  EXPECT_EQ(near.points_so_far(test::exec()), 2 * n);  // summed on the device
  EXPECT_EQ(every.points_so_far(test::exec()), n);
}

// The domain quadrature's transfer is the full-order step's on particle domains: from a state its map
// decodes exactly (a cube strained about its centre, F = I + E, moving at v̂), the samples' velocities after
// P2G through the corners, the grid update and G2P through the corners are the full-order particles' after
// one substep, to rounding, with corners enriched or not. The plain material-point quadrature, on the same
// state, is not (its stencils' forces differ at the surface), which is what this test tells apart.
struct StrainedCube {
  static constexpr float kDx = 1.0f / 32.0f, kDt = 1e-3f;
  Mat3<float> E;
  Vec3<float> center = Vec3<float>::constant(0.5f);
  Vec3<float> velocity{0.5f, 0.0f, -0.25f};
  mpm::ParticleInit reference =
      test::lattice_box_with_domains(Vec3<float>::constant(0.4375f), Vec3<float>::constant(0.5625f), kDx, 2, 1000.0f);
  FullOrderConfig config = test::open_space_config(kDx, 32, scene::nclaw_material(scene::NclawMaterial::Jelly));

  explicit StrainedCube(const Mat3<float>& strain) : E(strain) {
    config.gravity = Vec3<float>(0.0f, -9.81f, 0.0f);
    config.transfer = mpm::Transfer::PicFlip;
    config.flip_alpha = 0.0f;
  }
  Vec3<float> strained(const Vec3<float>& X) const { return X + E * (X - center); }

  // The full-order particles' velocities after one substep from the strained state, and the share of its
  // domains that enriched their corners.
  std::pair<std::vector<float>, double> full_order_velocities() const {
    mpm::ParticleInit init = reference;
    const Index n = init.count();
    init.F.assign(std::size_t(9 * n), 0.0f);
    const Mat3<float> F = Mat3<float>::identity() + E;
    for (Index p = 0; p < n; ++p) {
      test::set_plane_vector(init.x, n, p, strained(test::plane_vector(reference.x, n, p)));
      test::set_plane_vector(init.v, n, p, velocity);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) init.F[std::size_t((3 * r + c) * n + p)] = F(r, c);
    }
    const Index corners = init.domains.corner_count();
    init.domains.resumed_corner_x = init.domains.corner_x;
    for (Index c = 0; c < corners; ++c)
      test::set_plane_vector(init.domains.resumed_corner_x, corners, c,
                             strained(test::plane_vector(init.domains.corner_x, corners, c)));
    FullOrderSim sim(test::exec(), config, init);
    sim.substep(kDt);
    return {sim.particles().velocities_in_initial_order(sim.exec()), sim.enriched_share()};
  }

  // The samples' velocities after one reduced substep's transfers (every point a sample), through the domain
  // quadrature or the material points' own stencils.
  std::vector<float> reduced_velocities(bool domains) const {
    const Exec& exec = test::exec();
    const ReferenceBody body(exec.backend, reference);
    const DeformationMap map(exec.backend, test::strained_translation_map(E, center));
    const DeviceBuffer<float> latent =
        DeviceBuffer<float>::from_host(exec.backend, {0.0f, 0.0f, 0.0f, velocity[0], velocity[1], velocity[2]});
    const Span<const float> xhat = latent.span().subspan(0, 3), vhat = latent.span().subspan(3, 3);
    SampleSet samples(reference, 0, 0, 0, 1, 3);
    samples.draw(exec, body);
    samples.decode(exec, map, xhat, vhat);
    std::optional<DomainQuadrature> through_domains;
    std::optional<LagrangianQuadrature> own_stencils;
    ReducedQuadrature& quadrature =
        domains ? static_cast<ReducedQuadrature&>(through_domains.emplace(
                      exec, body, reference.domains, reference.domain, 3, config.enrichment_threshold))
                : own_stencils.emplace(exec, body, 3, kDx, /*search=*/false);
    const mpm::ParticleView points = quadrature.build(exec, map, samples, xhat, vhat);
    mpm::SparseGrid grid(exec.backend, kDx, /*keep_old_velocity=*/false);
    grid.rebuild(exec, quadrature.sample_stencil_points(samples));
    // The reduced step runs PIC as its kernels' APIC with C = 0 (ReducedSim's configuration).
    FullOrderConfig reduced_config = config;
    reduced_config.transfer = mpm::Transfer::Apic;
    StepInputs inputs(exec, reduced_config);
    const mpm::StepParams step = inputs.at(0.0, kDt);
    quadrature.particles_to_grid(exec, points, grid.view(), step);
    mpm::update_grid(exec, grid.view(), step);
    quadrature.grid_to_samples(exec, samples, grid.view(), step);
    return host(exec, samples.points().v, 3 * samples.count());
  }
};

float largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  float largest = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::fabs(a[i] - b[i]));
  return largest;
}

// The change of the particles' velocities from free fall in the full-order substep (the stress's), checked to
// be large, and how far the domain quadrature's samples are from the full-order particles.
struct Agreement {
  float stress_change, through_domains, own_stencils;
};
Agreement domain_agreement(const StrainedCube& cube, bool enriched) {
  const auto [full, enriched_share] = cube.full_order_velocities();
  EXPECT_EQ(enriched_share > 0.0, enriched);
  const Index n = cube.reference.count();
  EXPECT_EQ(full.size(), std::size_t(3 * n));
  // The stress moved the surface: some particle's velocity changed by far more than gravity's 1 cm/s.
  std::vector<float> free_fall(full.size());
  for (Index p = 0; p < n; ++p)
    test::set_plane_vector(free_fall, n, p, cube.velocity + StrainedCube::kDt * cube.config.gravity);
  const float stress_change = largest_difference(full, free_fall);
  EXPECT_GT(stress_change, 0.05f);
  return {stress_change, largest_difference(cube.reduced_velocities(/*domains=*/true), full),
          largest_difference(cube.reduced_velocities(/*domains=*/false), full)};
}

TEST(DomainQuadrature, SamplesMoveAsTheFullOrderStepOnDomainsMovesTheirParticles) {
  Mat3<float> E = Mat3<float>::zero();
  E(0, 0) = 0.10f, E(0, 1) = 0.05f, E(1, 1) = -0.08f, E(1, 2) = 0.03f, E(2, 0) = 0.02f, E(2, 2) = 0.06f;
  const Agreement agreement = domain_agreement(StrainedCube(E), /*enriched=*/false);
  // Through the domains: the full-order velocities to float rounding of sums of that size, in other orders
  // (seen: 6e-6 m/s of a 0.55 m/s change).
  EXPECT_LT(agreement.through_domains, 2e-5f);
  // Through the points' own stencils: off by a share of the change (seen: 0.063 m/s, 11 %).
  EXPECT_GT(agreement.own_stencils, 0.05f * agreement.stress_change);
}

// Stretched to four times its length (F = diag(4, 1, 1), quality 3 / (‖F‖ ‖F⁻¹‖) = 0.49 under the threshold
// 0.6), every domain enriches its corners, which then integrate on their own in both steps.
TEST(DomainQuadrature, EnrichedCornersMoveAsTheFullOrderStepMovesThem) {
  Mat3<float> E = Mat3<float>::zero();
  E(0, 0) = 3.0f;
  const Agreement agreement = domain_agreement(StrainedCube(E), /*enriched=*/true);
  EXPECT_LT(agreement.through_domains, 4e-5f * agreement.stress_change);
  EXPECT_GT(agreement.own_stencils, 0.05f * agreement.stress_change);
}

TEST(DomainQuadrature, NeedsEveryMaterialPointInADomain) {
  const mpm::ParticleInit plain = body();
  const ReferenceBody reference(test::exec().backend, plain);
  const mpm::ParticleInit with_domains =
      test::lattice_box_with_domains(Vec3<float>::constant(0.49f), Vec3<float>::constant(0.51f), 0.01f, 2, 1000.0f);
  EXPECT_THROW(
      {
        try {
          DomainQuadrature(test::exec(), reference, plain.domains, plain.domain, 3, 0.6f);
        } catch (const Error& error) {
          EXPECT_NE(std::string(error.what()).find("domains = true"), std::string::npos) << error.what();
          throw;
        }
      },
      Error);
  std::vector<std::int32_t> one_without = with_domains.domain;
  one_without[7] = mpm::kNoDomain;
  const ReferenceBody same_body(test::exec().backend, with_domains);
  EXPECT_THROW(DomainQuadrature(test::exec(), same_body, with_domains.domains, one_without, 3, 0.6f), Error);
}

}  // namespace
}  // namespace romp::engine
