// DomainConfig<T>: the domain, its grid, walls, gravity and time stepping of an MPM simulation: what a
// scene (scene::Scene), the engine (FullOrderConfig) and the differentiable step (nn::DiffMpmConfig)
// share. Each of them is a DomainConfig, so the fields, their meaning and their defaults are written once.
#pragma once

#include <array>
#include <cstdint>

#include "kernels/math/vec3.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/domain_walls.h"

namespace romp::mpm {

// Templated on the scalar because each holder keeps it in the precision it computes in: a scene as
// parsed in double; the engine in float, as its kernels and its CFL arithmetic have always been; the
// differentiable step in double, since its gradient checks run the kernels in double (training
// narrows to float where it builds its StepParams). converted<U>() is the one place the scalar changes
// when one holder is built from another.
template <class T>
struct DomainConfig {
  T dx = T(0);                                        // m, the side of a grid cell
  std::array<std::int32_t, 3> domain_cells{0, 0, 0};  // the domain is [0, cells dx] per axis
  Vec3<T> gravity{T(0), T(-9.81), T(0)};              // m/s²
  std::int32_t wall_cells = 3;                        // nodes this close to a domain face are wall nodes
  ContactType wall_contact = ContactType::Separate;
  T wall_friction = T(0);  // Coulomb friction of Separate walls; the differentiable step has none
  T fixed_dt = T(0);       // s; > 0: every substep takes this Δt (the differentiable step needs one)
  T cfl = T(0.5);          // else Δt = cfl dx / (c + |v|max); at most 1, or kImplicitMaxCfl when implicit
  T max_dt = T(1e-3);      // s; upper bound on the CFL step (a body at rest has |v| = 0)

  // The box and its walls as the kernels' StepParams take them.
  Domain domain() const {
    Domain d;
    for (int a = 0; a < 3; ++a) d.cells[a] = domain_cells[std::size_t(a)];
    d.wall_cells = wall_cells;
    d.wall_contact = wall_contact;
    return d;
  }

  template <class U>
  DomainConfig<U> converted() const {
    DomainConfig<U> c;
    c.dx = U(dx);
    c.domain_cells = domain_cells;
    c.gravity = Vec3<U>(U(gravity[0]), U(gravity[1]), U(gravity[2]));
    c.wall_cells = wall_cells;
    c.wall_contact = wall_contact;
    c.wall_friction = U(wall_friction);
    c.fixed_dt = U(fixed_dt);
    c.cfl = U(cfl);
    c.max_dt = U(max_dt);
    return c;
  }
};

}  // namespace romp::mpm
