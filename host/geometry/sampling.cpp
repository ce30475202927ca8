// Turning shapes into particles: lattice, jittered-lattice and Poisson-disk sampling, and appending bodies.
#include "host/geometry/sampling.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "host/geometry/poisson_disk.h"
#include "host/geometry/random.h"
#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

// Lattice points one sampling may visit at most: beyond this a mistyped dx would exhaust memory
// long before it finished.
constexpr double kMaxLatticePoints = 2e9;

// The indices i with (i + 0.5) h in [low − margin, high + margin] per axis, one more on each side
// so rounding cannot drop a point; the inside test decides the rest.
struct LatticeRange {
  std::int64_t begin[3], end[3];  // [begin, end)
};

LatticeRange lattice_range(const Shape& shape, double h, double margin) {
  const Bounds bounds = shape.bounds();
  LatticeRange range;
  double count = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double first = std::floor((bounds.low[a] - margin) / h - 0.5);
    const double last = std::ceil((bounds.high[a] + margin) / h - 0.5);
    count *= last - first + 1.0;
    if (!(count <= kMaxLatticePoints))
      throw Error(
          fmt::format("{}: sampling at spacing h = {} would visit more than {:g} lattice points; raise dx or "
                      "lower per_cell",
                      shape.describe(), h, kMaxLatticePoints));
    range.begin[a] = std::int64_t(first);
    range.end[a] = std::int64_t(last) + 1;
  }
  return range;
}

// Calls visit(point) for the lattice points of `range`, x slowest and z fastest.
template <class Visit>
void for_each_lattice_point(const LatticeRange& range, double h, Visit&& visit) {
  for (std::int64_t i = range.begin[0]; i < range.end[0]; ++i)
    for (std::int64_t j = range.begin[1]; j < range.end[1]; ++j)
      for (std::int64_t k = range.begin[2]; k < range.end[2]; ++k)
        visit(Vec3<double>((double(i) + 0.5) * h, (double(j) + 0.5) * h, (double(k) + 0.5) * h));
}

std::size_t count_lattice_points_inside(const Shape& shape, double h) {
  std::size_t inside = 0;
  for_each_lattice_point(lattice_range(shape, h, 0.0), h, [&](const Vec3<double>& p) { inside += shape.contains(p); });
  return inside;
}

void validate(const SamplingSpec& spec) {
  if (spec.per_cell < 1) throw Error(fmt::format("sampling: per_cell must be >= 1, got {}", spec.per_cell));
  if (!(spec.dx > 0.0) || !std::isfinite(spec.dx))
    throw Error(fmt::format("sampling: the grid spacing dx must be finite and > 0, got {}", spec.dx));
  if (!(spec.jitter >= 0.0 && spec.jitter <= 1.0))
    throw Error(fmt::format("sampling: jitter must lie in [0, 1] (a fraction of the spacing), got {}", spec.jitter));
}

}  // namespace

SampledBody sample(const Shape& shape, const SamplingSpec& spec) {
  validate(spec);
  const double h = spec.spacing();
  const double cell_volume = h * h * h;
  SampledBody body;
  std::size_t lattice_inside = 0;
  switch (spec.method) {
    case SamplingMethod::Lattice:
      for_each_lattice_point(lattice_range(shape, h, 0.0), h, [&](const Vec3<double>& p) {
        if (shape.contains(p)) body.points.push_back(p);
      });
      lattice_inside = body.points.size();
      break;
    case SamplingMethod::JitteredLattice: {
      // Points up to h/2 outside the bounds may move in; all three offsets are drawn for every
      // lattice point, so the sequence does not depend on which points land inside.
      Random random(spec.seed);
      const double reach = 0.5 * spec.jitter * h;
      for_each_lattice_point(lattice_range(shape, h, 0.5 * h), h, [&](const Vec3<double>& p) {
        lattice_inside += shape.contains(p);
        Vec3<double> moved;
        for (int a = 0; a < 3; ++a) moved[a] = p[a] + random.uniform(-reach, reach);
        if (shape.contains(moved)) body.points.push_back(moved);
      });
      break;
    }
    case SamplingMethod::PoissonDisk: {
      lattice_inside = count_lattice_points_inside(shape, h);
      // Sampled beyond the bounds too, so the shape's surface sees the density of the interior
      // rather than the denser packing Bridson's algorithm leaves along the region's faces.
      const double radius = kPoissonRadiusPerSpacing * h;
      Bounds region = shape.bounds();
      region.low -= Vec3<double>::constant(2.0 * radius);
      region.high += Vec3<double>::constant(2.0 * radius);
      for (const Vec3<double>& p : poisson_disk_sample(region, radius, spec.seed))
        if (shape.contains(p)) body.points.push_back(p);
      break;
    }
  }
  if (body.points.empty() || lattice_inside == 0)
    throw Error(
        fmt::format("{} holds no lattice point at spacing h = {} (dx {} / {} per cell): it is smaller than "
                    "the spacing; refine dx or raise per_cell",
                    shape.describe(), h, spec.dx, spec.per_cell));
  body.particle_volume = double(lattice_inside) * cell_volume / double(body.points.size());
  return body;
}

void append_body(mpm::ParticleInit& init, const SampledBody& body, double density, std::int32_t material) {
  ROMP_CHECK(density > 0.0 && std::isfinite(density), fmt::format("density must be finite and > 0, got {}", density));
  ROMP_CHECK(body.particle_volume > 0.0, "a sampled body's particle volume must be > 0");
  const Index old_count = init.count();
  ROMP_CHECK(Index(init.x.size()) == 3 * old_count && Index(init.v.size()) == 3 * old_count &&
                 Index(init.volume0.size()) == old_count && Index(init.material.size()) == old_count &&
                 Index(init.dirichlet_group.size()) == old_count,
             "ParticleInit arrays disagree on the particle count");
  const Index added = Index(body.points.size());
  const Index count = old_count + added;
  // The planes are component-major over the total count, so every old plane moves.
  const auto grow_planes = [&](const std::vector<float>& old_planes, auto&& new_value) {
    std::vector<float> planes(std::size_t(3 * count));
    for (int a = 0; a < 3; ++a) {
      std::copy(old_planes.begin() + a * old_count, old_planes.begin() + (a + 1) * old_count,
                planes.begin() + a * count);
      for (Index p = 0; p < added; ++p) planes[std::size_t(a * count + old_count + p)] = new_value(p, a);
    }
    return planes;
  };
  init.x = grow_planes(init.x, [&](Index p, int a) { return float(body.points[std::size_t(p)][a]); });
  init.v = grow_planes(init.v, [](Index, int) { return 0.0f; });
  init.mass.insert(init.mass.end(), std::size_t(added), float(density * body.particle_volume));
  init.volume0.insert(init.volume0.end(), std::size_t(added), float(body.particle_volume));
  init.material.insert(init.material.end(), std::size_t(added), material);
  init.dirichlet_group.insert(init.dirichlet_group.end(), std::size_t(added), mpm::kNoDirichletGroup);
  if (!init.domain.empty()) init.domain.insert(init.domain.end(), std::size_t(added), mpm::kNoDomain);
}

mpm::ParticleInit sample_box(const Vec3<float>& low, const Vec3<float>& high, const SamplingSpec& spec,
                             double density) {
  const Vec3<double> lo(low[0], low[1], low[2]), hi(high[0], high[1], high[2]);
  mpm::ParticleInit init;
  append_body(init, sample(Box{(lo + hi) * 0.5, (hi - lo) * 0.5}, spec), density, 0);
  return init;
}

}  // namespace romp::geometry
