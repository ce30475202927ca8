// The box both MPMs simulate in, [0, cells dx]³: its wall bands, the frictionless wall rule on a
// node's velocity, and the band particles are kept inside. The engine (float, sparse grid) and the
// differentiable step (float or double, dense grid) both apply these, so their walls are one rule.
#pragma once

#include <cstdint>

#include "kernels/core/hd.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/contact.h"

namespace romp::mpm {

// Particles strictly inside the domain by this many cells: their stencil never leaves [0, L]^3, and
// the truncation in QuadraticStencil is a floor.
inline constexpr float kDomainMarginCells = 1.0f;

// The spacing dx is not part of it: the engine's grid holds its own, the differentiable step its own.
struct Domain {
  std::int32_t cells[3] = {0, 0, 0};  // the domain is [0, cells dx] per axis; cells + 1 nodes per axis
  std::int32_t wall_cells = 0;        // nodes this close to a domain face are wall nodes
  ContactType wall_contact = ContactType::Separate;

  // Whether a point at coordinate x along `axis` lies within wall_cells cells of the low face (inward
  // normal +e_axis) or of the high face (inward normal −e_axis). For a grid node (x = index × dx) this
  // is the test index < wall_cells exactly: products of integers by one dx keep their order.
  template <class T>
  ROMP_HD bool near_low_wall(T x, T dx) const {
    return x < T(wall_cells) * dx;
  }
  template <class T>
  ROMP_HD bool near_high_wall(int axis, T x, T dx) const {
    return x > T(cells[axis] - wall_cells) * dx;
  }

  // The band particles are kept in, kDomainMarginCells inside each face.
  template <class T>
  ROMP_HD T low_bound(T dx) const {
    return T(kDomainMarginCells) * dx;
  }
  template <class T>
  ROMP_HD T high_bound(int axis, T dx) const {
    return (T(cells[axis]) - T(kDomainMarginCells)) * dx;
  }
};

// The velocity components a point at x keeps (1) or loses (0) under frictionless wall contact, given
// its velocity v before the walls: Sticky walls take all of it, Slip the normal component both ways,
// Separate only the normal component toward the wall. As a mask the rule is the same for resolve_contact
// applied face by face with zero friction (an axis normal changes only its own component), and the
// differentiable step's adjoint applies the same mask; the engine adds Coulomb friction on top
// (resolve_walls in grid_boundary.h).
template <class T>
ROMP_HD_INLINE Vec3<T> wall_keep_mask(const Domain& domain, const Vec3<T>& x, T dx, const Vec3<T>& v) {
  Vec3<T> keep = Vec3<T>::constant(T(1));
  for (int a = 0; a < 3; ++a) {
    const bool low = domain.near_low_wall(x[a], dx);
    const bool high = domain.near_high_wall(a, x[a], dx);
    if (!low && !high) continue;
    if (domain.wall_contact == ContactType::Sticky) return Vec3<T>::zero();
    const bool approaching = (low && v[a] < T(0)) || (high && v[a] > T(0));
    if (domain.wall_contact == ContactType::Slip || approaching) keep[a] = T(0);
  }
  return keep;
}

// Coordinate `axis` of a position moved back into the band where it left it, so its stencil stays on
// the grid (walls normally stop particles and corners well before). NaN (a state gone non-finite)
// goes to the low bound: the next substep's stencil must index inside the grid whatever happened. The
// engine still sees such a particle fail, by its velocity (x' = x + dt v from a finite x is NaN only
// when v is).
template <class T>
ROMP_HD_INLINE T clamp_to_domain(const Domain& domain, T x, int axis, T dx) {
  const T low = domain.low_bound(dx);
  return math::select(x >= low, math::min(x, domain.high_bound(axis, dx)), low);
}

template <class T>
ROMP_HD_INLINE Vec3<T> kept_inside_domain(const Domain& domain, Vec3<T> x, T dx) {
  for (int a = 0; a < 3; ++a) x[a] = clamp_to_domain(domain, x[a], a, dx);
  return x;
}

}  // namespace romp::mpm
