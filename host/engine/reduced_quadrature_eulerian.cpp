// The Eulerian quadrature (ROM paper, Alg. 4): points on a lattice in the cells around the samples,
// placed in the reference configuration by inverting g.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include "host/engine/reduced_quadrature.h"
#include "host/geometry/bounds.h"
#include "kernels/core/error.h"

namespace romp::engine {
EulerianQuadrature::EulerianQuadrature(const Exec& exec, const mpm::ParticleInit& reference, EulerianSettings settings)
    : settings_(std::move(settings)) {
  const Index n = reference.count();
  // Cells as fine as the finest sampling: h = cbrt(the smallest particle volume).
  const float h = std::cbrt(*std::min_element(reference.volume0.begin(), reference.volume0.end()));
  const geometry::Bounds box = geometry::bounds_of_planes(reference.x, n);
  const Vec3<float> low(float(box.low[0]), float(box.low[1]), float(box.low[2]));
  const Vec3<float> high(float(box.high[0]), float(box.high[1]), float(box.high[2]));
  rom::ReferenceOccupancy occupancy;
  occupancy.inverse_h = 1.0f / h;
  // The origin on the sampling lattice (points at (i + ½) h), so a lattice point's cube is one cell.
  for (int a = 0; a < 3; ++a) {
    occupancy.origin[a] = (std::floor(low[a] / h) - 2.0f) * h;
    occupancy.cells[a] = int(std::ceil((high[a] - occupancy.origin[a]) / h)) + 3;
  }
  const Index cells = Index(occupancy.cells[0]) * occupancy.cells[1] * occupancy.cells[2];
  ROMP_CHECK(cells < (Index(1) << 31), "the reference configuration's occupancy grid would exceed 2^31 cells");
  std::vector<std::int32_t> material_plus_one(static_cast<std::size_t>(cells), 0);
  // Each point owns the cells whose centres lie in its cube of side cbrt(volume) about it.
  for (Index p = 0; p < n; ++p) {
    const float half = 0.5f * std::cbrt(reference.volume0[p]);
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      const float X = reference.x[a * n + p];
      first[a] = std::max(0, int(std::ceil((X - half - occupancy.origin[a]) / h - 0.5f)));
      last[a] = std::min(occupancy.cells[a] - 1, int(std::ceil((X + half - occupancy.origin[a]) / h - 0.5f)) - 1);
    }
    for (int k = first[2]; k <= last[2]; ++k)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int i = first[0]; i <= last[0]; ++i)
          material_plus_one[std::size_t((Index(k) * occupancy.cells[1] + j) * occupancy.cells[0] + i)] =
              reference.material[p] + 1;
  }
  occupancy_cells_ = DeviceBuffer<std::int32_t>::from_host(exec.backend, material_plus_one);
  occupancy.material_plus_one = Span<const std::int32_t>(occupancy_cells_.data(), occupancy_cells_.size());
  occupancy_ = occupancy;
  densities_ = DeviceBuffer<float>::from_host(exec.backend, settings_.densities);
  tally_ = DeviceBuffer<rom::QuadratureTally>(exec.backend, 1);
  tally_.fill_zero(exec.stream);
}

mpm::ParticleView EulerianQuadrature::build(const Exec& exec, const DeformationMap& map, const SampleSet& samples,
                                            Span<const float> xhat, Span<const float> vhat) {
  // Alg. 4, step 3: ℓ³ points in each cell whose points may reach a sample's grid nodes, of which only
  // those whose stencils reach them (unless the lattice keeps them all), built and counted on the device:
  // `count` slots hold them, the first point_count_[0] of which are points, and every launch below runs
  // over the slots and stops there.
  const rom::SampleNeighbourhood::Points built =
      neighbourhood_.build_eulerian_points(exec, samples.X(), samples.x(), samples.F(), settings_.lattice);
  const Index count = built.bound;
  point_count_ = built.count;
  // The slots are a fixed bound for few samples and follow the cells found for many: the buffers grow with
  // headroom and are otherwise reused.
  if (points_.resize(exec.backend, count)) {
    // No Eulerian point is a material point or in a Dirichlet group; set once for the whole capacity.
    const Index capacity = points_.capacity;
    std::vector<std::int32_t> none(static_cast<std::size_t>(capacity), mpm::kNoDirichletGroup), ids(none.size());
    std::iota(ids.begin(), ids.end(), 0);
    points_.group.copy_from_host(Span<const std::int32_t>(none.data(), capacity), exec.stream);
    points_.id.copy_from_host(Span<const std::int32_t>(ids.data(), capacity), exec.stream);
  }
  inversion_iterations_.ensure_size(exec.backend, count);
  map_evaluations_.ensure_size(exec.backend, count);
  jacobian_evaluations_.ensure_size(exec.backend, count);
  guesses_.ensure_size(exec.backend, 3 * count);
  guess_jacobians_.ensure_size(exec.backend, 9 * count);
  place_cells_.ensure_size(exec.backend, count);
  place_subs_.ensure_size(exec.backend, count);
  const Vec3Planes<float> guess(guesses_.data(), count);
  const Mat3Planes<float> guess_jacobian(guess_jacobians_.data(), count);
  neighbourhood_.write_eulerian_points(exec, Vec3Planes<float>(points_.x.data(), count), guess, guess_jacobian,
                                       place_cells_.prefix(count), place_subs_.prefix(count));
  if (settings_.warm_start && last_count_ >= 0) {
    rom::warm_start_inversions(exec, last_inversions(), xhat, place_cells_.prefix(count), place_subs_.prefix(count),
                               guess, guess_jacobian, tally_.span(), point_count_);
  }
  const float dx = settings_.lattice.dx;
  const int l = settings_.lattice.points_per_cell;
  const rom::EulerianPointsOut out{Vec3Planes<float>(points_.X.data(), count),
                                   Vec3Planes<float>(points_.v.data(), count),
                                   Mat3Planes<float>(points_.F.data(), count),
                                   points_.mass.prefix(count),
                                   points_.volume0.prefix(count),
                                   points_.material.prefix(count),
                                   points_.status.prefix(count),
                                   inversion_iterations_.prefix(count),
                                   map_evaluations_.prefix(count),
                                   jacobian_evaluations_.prefix(count)};
  rom::eulerian_quadrature(exec, map.view(), xhat, vhat, occupancy_, densities_.span(), dx * dx * dx / float(l * l * l),
                           settings_.inversion, Vec3Planes<const float>(points_.x.data(), count),
                           Vec3Planes<const float>(guess), Mat3Planes<const float>(guess_jacobian), out,
                           rom::MapKernel::Fastest, point_count_);
  rom::tally_quadrature(exec, out, count, tally_.span(), point_count_);
  if (settings_.warm_start) keep_for_warm_starts(exec, count, xhat, vhat);
  // Points outside the body (or unconverged) carry no mass; P2G would evaluate a stress for each of them,
  // so the used points are gathered into a set of their own, P2G's, counted on the device: the gathers
  // and P2G run over every inverted point's slot and stop at the count.
  used_index_.ensure_size(exec.backend, count);
  used_count_ = select_.select_on_device(exec, points_.status.prefix(count), rom::kQuadratureUsed, used_index_.span(),
                                         point_count_);
  used_.gather_from(exec, points_, used_index_.prefix(count), used_count_);
  return used_.view();
}

rom::Inversions EulerianQuadrature::last_inversions() const {
  const Index n = last_count_;
  return {last_cells_.prefix(n),
          last_subs_.prefix(n),
          last_status_.prefix(n),
          Vec3Planes<const float>(last_X_.data(), n),
          Vec3Planes<const float>(last_v_.data(), n),
          Mat3Planes<const float>(last_F_.data(), n),
          last_xhat_.span(),
          last_vhat_.span(),
          last_point_count_.prefix(1)};
}

void EulerianQuadrature::keep_for_warm_starts(const Exec& exec, Index count, Span<const float> xhat,
                                              Span<const float> vhat) {
  last_point_count_.ensure_size(exec.backend, 1);
  last_cells_.ensure_size(exec.backend, count);
  last_subs_.ensure_size(exec.backend, count);
  last_status_.ensure_size(exec.backend, count);
  last_X_.ensure_size(exec.backend, 3 * count);
  last_v_.ensure_size(exec.backend, 3 * count);
  last_F_.ensure_size(exec.backend, 9 * count);
  if (last_xhat_.size() != xhat.size()) {  // the map's r values in every build: sized once
    last_xhat_ = DeviceBuffer<float>(exec.backend, xhat.size());
    last_vhat_ = DeviceBuffer<float>(exec.backend, vhat.size());
  }
  const rom::Inversions now{place_cells_.prefix(count),
                            place_subs_.prefix(count),
                            points_.status.prefix(count),
                            Vec3Planes<const float>(points_.X.data(), count),
                            Vec3Planes<const float>(points_.v.data(), count),
                            Mat3Planes<const float>(points_.F.data(), count),
                            xhat,
                            vhat,
                            point_count_};
  rom::keep_inversions(
      exec, now,
      {last_cells_.prefix(count), last_subs_.prefix(count), last_status_.prefix(count),
       Vec3Planes<float>(last_X_.data(), count), Vec3Planes<float>(last_v_.data(), count),
       Mat3Planes<float>(last_F_.data(), count), last_xhat_.span(), last_vhat_.span(), last_point_count_.prefix(1)});
  last_count_ = count;
}

Index EulerianQuadrature::last_count(const Exec& exec) const {
  return point_count_.empty() ? 0 : Index(download(exec.backend, point_count_, exec.stream)[0]);
}

mpm::PointSource EulerianQuadrature::failure_source() const {
  return {Vec3Planes<const float>(used_.x.data(), used_.count),
          Vec3Planes<const float>(used_.X.data(), used_.count),
          {},
          /*particles=*/false};
}

std::string EulerianQuadrature::describe(const mpm::FailedPoint& point) const {
  // An Eulerian point is no material point: it is named by where it is.
  return fmt::format(
      "the Eulerian quadrature point at x = ({:.4g}, {:.4g}, {:.4g}) m, reference X = ({:.4g}, {:.4g}, "
      "{:.4g}) m",
      point.x[0], point.x[1], point.x[2], point.X[0], point.X[1], point.X[2]);
}

}  // namespace romp::engine
