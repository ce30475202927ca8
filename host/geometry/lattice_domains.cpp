// Lattice cells as particle domains: corner deduplication by lattice vertex, weights by Gauss quadrature.
#include "host/geometry/lattice_domains.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "host/geometry/primitives.h"
#include "kernels/core/error.h"
#include "kernels/mpm/hex_domain.h"

namespace romp::geometry {

void append_lattice_domains(mpm::ParticleInit& init, Index first, const SampledBody& body, double spacing) {
  const Index n = init.count();
  const Index added = Index(body.points.size());
  ROMP_CHECK(spacing > 0.0 && first >= 0 && first + added == n,
             "append_lattice_domains: the body must be the last one appended to the particles");
  init.domain.resize(std::size_t(n), mpm::kNoDomain);
  mpm::DomainInit& domains = init.domains;

  // Corner positions of the new corners, kept as lattice vertices until the planes are rebuilt.
  std::map<std::array<std::int64_t, 3>, std::int32_t> corner_of_vertex;
  std::vector<std::array<std::int64_t, 3>> new_vertices;
  const Index old_corners = domains.corner_count();

  for (Index i = 0; i < added; ++i) {
    const Vec3<double>& x = body.points[std::size_t(i)];
    std::array<std::int64_t, 3> cell{};
    for (int a = 0; a < 3; ++a) {
      const double index = x[a] / spacing - 0.5;
      cell[a] = std::int64_t(std::llround(index));
      ROMP_CHECK(std::abs(index - double(cell[a])) < 1e-6,
                 fmt::format("particle domains need lattice sampling: point ({}, {}, {}) is not a centre of the "
                             "lattice of spacing {}",
                             x[0], x[1], x[2], spacing));
    }
    Vec3<double> reference[mpm::kDomainCorners];
    for (int c = 0; c < mpm::kDomainCorners; ++c) {
      const std::array<std::int64_t, 3> vertex{cell[0] + (c >> 2), cell[1] + ((c >> 1) & 1), cell[2] + (c & 1)};
      for (int a = 0; a < 3; ++a) reference[c][a] = double(vertex[a]) * spacing;
      const auto [found, inserted] =
          corner_of_vertex.emplace(vertex, std::int32_t(old_corners + Index(new_vertices.size())));
      if (inserted) new_vertices.push_back(vertex);
      domains.corner.push_back(found->second);
    }
    const mpm::HexDomainWeights<double> weights = mpm::hex_domain_weights(reference);
    for (int c = 0; c < mpm::kDomainCorners; ++c) {
      domains.weight.push_back(float(weights.weight[c]));
      for (int a = 0; a < 3; ++a) domains.gradient.push_back(float(weights.gradient[c][a]));
    }
    init.domain[std::size_t(first + i)] = std::int32_t(domains.count() - 1);
  }

  const Index corners = old_corners + Index(new_vertices.size());
  std::vector<float> corner_x(std::size_t(3 * corners));
  for (int a = 0; a < 3; ++a) {
    std::copy_n(domains.corner_x.begin() + a * old_corners, old_corners, corner_x.begin() + a * corners);
    for (std::size_t v = 0; v < new_vertices.size(); ++v)
      corner_x[std::size_t(a * corners + old_corners) + v] = float(double(new_vertices[v][a]) * spacing);
  }
  domains.corner_x = std::move(corner_x);
  domains.corner_dirichlet_group.resize(std::size_t(corners), mpm::kNoDirichletGroup);
}

mpm::ParticleInit sample_box_with_domains(const Vec3<float>& low, const Vec3<float>& high, const SamplingSpec& spec,
                                          double density) {
  const Vec3<double> lo(low[0], low[1], low[2]), hi(high[0], high[1], high[2]);
  const SampledBody body = sample(Box{(lo + hi) * 0.5, (hi - lo) * 0.5}, spec);
  mpm::ParticleInit init;
  append_body(init, body, density, 0);
  append_lattice_domains(init, 0, body, spec.spacing());
  return init;
}

void assign_corner_dirichlet_groups(mpm::ParticleInit& init) {
  mpm::DomainInit& domains = init.domains;
  std::fill(domains.corner_dirichlet_group.begin(), domains.corner_dirichlet_group.end(), mpm::kNoDirichletGroup);
  for (std::size_t p = 0; p < init.domain.size(); ++p) {
    const std::int32_t d = init.domain[p], group = init.dirichlet_group[p];
    if (d == mpm::kNoDomain || group == mpm::kNoDirichletGroup) continue;
    for (int c = 0; c < mpm::kDomainCorners; ++c) {
      std::int32_t& corner_group =
          domains.corner_dirichlet_group[std::size_t(domains.corner[std::size_t(mpm::kDomainCorners * d + c)])];
      if (corner_group == mpm::kNoDirichletGroup || group < corner_group) corner_group = group;
    }
  }
}

}  // namespace romp::geometry
