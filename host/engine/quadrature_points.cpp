// Quadrature point storage and the reference body's gathers.
#include "host/engine/quadrature_points.h"

#include <numeric>
#include <vector>

#include "kernels/core/gather_planes.h"

namespace romp::engine {
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
  GatheredArrays arrays;
  arrays.add(source.x.span(), x.span(), 3).add(source.X.span(), X.span(), 3).add(source.v.span(), v.span(), 3);
  arrays.add(source.F.span(), F.span(), 9).add(source.mass.span(), mass.span(), 1);
  arrays.add(source.volume0.span(), volume0.span(), 1).add(source.material.span(), material.span(), 1);
  arrays.add(source.group.span(), group.span(), 1).add(source.id.span(), id.span(), 1);
  gather_arrays(exec, arrays, n, index, live);
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

GatheredArrays ReferenceBody::arrays_into(QuadraturePoints& points) const {
  GatheredArrays arrays;
  arrays.add(X.span(), points.X.span(), 3).add(mass.span(), points.mass.span(), 1);
  arrays.add(volume0.span(), points.volume0.span(), 1).add(material.span(), points.material.span(), 1);
  arrays.add(group.span(), points.group.span(), 1).add(id.span(), points.id.span(), 1);
  return arrays;
}

void ReferenceBody::gather(const Exec& exec, Span<const std::int32_t> index, QuadraturePoints& points) const {
  gather_arrays(exec, arrays_into(points), count, index);
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
