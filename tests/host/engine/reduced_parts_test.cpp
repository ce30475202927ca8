// The reduced step's parts alone, on both backends: the sample set (hyper-reduction's draws, decoded
// kinematics), the projections of the latent state and the Lagrangian quadrature, under the translation
// map g(X; x̂) = X + x̂ whose every answer is known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "host/engine/deformation_map.h"
#include "host/engine/latent_projection.h"
#include "host/engine/quadrature_points.h"
#include "host/engine/reduced_quadrature.h"
#include "host/engine/sample_set.h"
#include "kernels/core/memory.h"
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

}  // namespace
}  // namespace romp::engine
