// Quadrature point storage and the reference body's gathers.
#include "host/engine/quadrature_points.h"

#include <numeric>
#include <vector>

#include "kernels/core/gather_planes.h"

namespace romp::engine {
namespace {

template <class T>
void gather_into(const Exec& exec, const DeviceBuffer<T>& source, Index source_count, int components,
                 Span<const std::int32_t> index, DeviceBuffer<T>& destination, Span<const std::int64_t> live = {}) {
  gather_planes(exec, source.span(), source_count, components, index, destination.span(), live);
}

}  // namespace

void QuadraturePoints::allocate(Backend backend, Index n) {
  count = n;
  capacity = n;
  for (DeviceBuffer<float>* planes : {&x, &X, &v}) *planes = DeviceBuffer<float>(backend, 3 * n);
  F = DeviceBuffer<float>(backend, 9 * n);
  C = DeviceBuffer<float>(backend, 9 * n);
  C.fill_zero();  // quadrature points carry no affine velocity: the transfer is PIC (ROM paper, Alg. 5)
  mass = DeviceBuffer<float>(backend, n);
  volume0 = DeviceBuffer<float>(backend, n);
  for (DeviceBuffer<std::int32_t>* ints : {&material, &group, &id, &status})
    *ints = DeviceBuffer<std::int32_t>(backend, n);
}

bool QuadraturePoints::resize(Backend backend, Index n) {
  const bool grows = n > capacity;
  if (grows) allocate(backend, n + n / 4);
  count = n;
  return grows;
}

void QuadraturePoints::gather_from(const Exec& exec, const QuadraturePoints& source, Span<const std::int32_t> index,
                                   Span<const std::int64_t> live) {
  const Index n = source.count;
  resize(exec.backend, index.size());
  gather_into(exec, source.x, n, 3, index, x, live);
  gather_into(exec, source.X, n, 3, index, X, live);
  gather_into(exec, source.v, n, 3, index, v, live);
  gather_into(exec, source.F, n, 9, index, F, live);
  gather_into(exec, source.mass, n, 1, index, mass, live);
  gather_into(exec, source.volume0, n, 1, index, volume0, live);
  gather_into(exec, source.material, n, 1, index, material, live);
  gather_into(exec, source.group, n, 1, index, group, live);
  gather_into(exec, source.id, n, 1, index, id, live);
}

mpm::ParticleView QuadraturePoints::view() {
  const Index n = count;
  return mpm::ParticleView{n,
                           Vec3Planes<float>(x.data(), n),
                           Vec3Planes<float>(v.data(), n),
                           Mat3Planes<float>(C.data(), n),
                           Mat3Planes<float>(F.data(), n),
                           mass.prefix(n),
                           volume0.prefix(n),
                           material.prefix(n),
                           group.prefix(n),
                           id.prefix(n)};
}

ReferenceBody::ReferenceBody(Backend backend, const mpm::ParticleInit& reference)
    : count(reference.count()),
      X(DeviceBuffer<float>::from_host(backend, reference.x)),
      mass(DeviceBuffer<float>::from_host(backend, reference.mass)),
      volume0(DeviceBuffer<float>::from_host(backend, reference.volume0)),
      material(DeviceBuffer<std::int32_t>::from_host(backend, reference.material)),
      group(DeviceBuffer<std::int32_t>::from_host(backend, reference.dirichlet_group)) {
  std::vector<std::int32_t> ids(static_cast<std::size_t>(count));
  std::iota(ids.begin(), ids.end(), 0);
  id = DeviceBuffer<std::int32_t>::from_host(backend, ids);
}

void ReferenceBody::gather(const Exec& exec, Span<const std::int32_t> index, QuadraturePoints& points) const {
  gather_into(exec, X, count, 3, index, points.X);
  gather_into(exec, mass, count, 1, index, points.mass);
  gather_into(exec, volume0, count, 1, index, points.volume0);
  gather_into(exec, material, count, 1, index, points.material);
  gather_into(exec, group, count, 1, index, points.group);
  gather_into(exec, id, count, 1, index, points.id);
}

void ReferenceBody::copy_to(QuadraturePoints& points) const {
  points.allocate(X.backend(), count);
  points.X = X.clone();
  points.mass = mass.clone();
  points.volume0 = volume0.clone();
  points.material = material.clone();
  points.group = group.clone();
  points.id = id.clone();
}

}  // namespace romp::engine
