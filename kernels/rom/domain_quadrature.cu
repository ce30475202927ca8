// The reduced step's domain kinematics and G2P at samples with domains: the launches behind domain_quadrature.h.
#include "kernels/rom/domain_quadrature.h"

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/domain_walls.h"
#include "kernels/mpm/stencil_nodes.h"

namespace romp::rom {
namespace {

using mpm::kDomainCorners;

struct PointsFromCorners {
  mpm::ParticleView points;
  mpm::DomainView domains;

  ROMP_HD void operator()(Index p) const {
    const Index d = points.domain[p];
    Vec3<float> x = Vec3<float>::zero(), v = Vec3<float>::zero();
    Mat3<float> F = Mat3<float>::zero();
    mpm::for_each_domain_corner(domains, d, [&](Index c, float w, const Vec3<float>& gradient) {
      const Vec3<float> x_corner = domains.x.load(c);
      x += w * x_corner;
      v += w * domains.v.load(c);
      F += Mat3<float>::outer(x_corner, gradient);
    });
    points.x.store(p, x);
    points.v.store(p, v);
    points.F.store(p, F);
    points.C.store(p, Mat3<float>::zero());
  }
};

struct GatherSampleCorners {
  Span<const std::int32_t> sample_point, point_domain;
  mpm::DomainView domains;
  Vec3Planes<float> corners;

  ROMP_HD void operator()(Index s) const {
    const Index d = point_domain[sample_point[s]];
    for (int a = 0; a < kDomainCorners; ++a)
      corners.store(kDomainCorners * s + a, domains.x.load(domains.corner[kDomainCorners * d + a]));
  }
};

struct GridToDomainSamples {
  mpm::ParticleView samples;
  Span<const std::int32_t> sample_point, point_domain;
  mpm::DomainView domains;
  Vec3Planes<const float> corners;
  mpm::GridView grid;
  mpm::StepParams step;

  ROMP_HD void operator()(Index s) const {
    Vec3<float> x = samples.x.load(s), v = Vec3<float>::zero();
    Mat3<float> C = Mat3<float>::zero(), F = samples.F.load(s);
    const std::int32_t group = samples.dirichlet_group[s];
    if (group != mpm::kNoDirichletGroup) {
      step.dirichlet[group].carry(step.dt, x, v, C, F);
    } else {
      const Index d = point_domain[sample_point[s]];
      for (int a = 0; a < kDomainCorners; ++a) {
        // A corner's velocity as grid_to_corners gives it: rigid in a Dirichlet group, its own where enriched,
        // the grid's otherwise.
        const Index entry = kDomainCorners * d + a, c = domains.corner[entry];
        const Vec3<float> x_corner = corners.load(kDomainCorners * s + a);
        const std::int32_t corner_group = domains.dirichlet_group[c];
        Vec3<float> v_corner = Vec3<float>::zero();
        if (corner_group != mpm::kNoDirichletGroup) {
          v_corner = step.dirichlet[corner_group].velocity_at(x_corner);
        } else if (domains.enriched[c]) {
          v_corner = domains.v.load(c);
        } else {
          const mpm::QuadraticStencil<float> stencil(x_corner, grid.inverse_dx);
          const mpm::StencilNodes nodes(stencil, grid.table);
          mpm::for_each_stencil_offset([&](int i, int j, int k) {
            v_corner += stencil.weight(i, j, k) * grid.velocity.load(nodes.node(i, j, k));
          });
        }
        v += domains.weight[entry] * v_corner;
      }
      x = mpm::kept_inside_domain(step.domain, x + step.dt * v, grid.dx);
    }
    mpm::store_moved_particle(samples, step, s, x, v, C, F);
  }
};

}  // namespace

void points_from_corners(const Exec& exec, const mpm::ParticleView& points, const mpm::DomainView& domains) {
  ROMP_CHECK(points.domain.size() == points.count, "points_from_corners needs every point's domain");
  for_each(exec, points.count, PointsFromCorners{points, domains});
}

void gather_sample_corners(const Exec& exec, Span<const std::int32_t> sample_point,
                           Span<const std::int32_t> point_domain, const mpm::DomainView& domains,
                           Vec3Planes<float> corners) {
  ROMP_CHECK(corners.count() == kDomainCorners * sample_point.size(), "gather_sample_corners: 8 corners per sample");
  for_each(exec, sample_point.size(), GatherSampleCorners{sample_point, point_domain, domains, corners});
}

void grid_to_domain_samples(const Exec& exec, const mpm::ParticleView& samples, Span<const std::int32_t> sample_point,
                            Span<const std::int32_t> point_domain, const mpm::DomainView& domains,
                            Vec3Planes<const float> corners, const mpm::GridView& grid, const mpm::StepParams& step) {
  ROMP_CHECK(sample_point.size() == samples.count, "grid_to_domain_samples: a material point per sample");
  for_each(exec, samples.count, GridToDomainSamples{samples, sample_point, point_domain, domains, corners, grid, step});
}

}  // namespace romp::rom
