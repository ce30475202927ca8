// Grid update: momentum to velocity, gravity, then domain walls and colliders.
#include "kernels/core/atomic.h"
#include "kernels/core/for_each.h"
#include "kernels/math/finite.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

struct UpdateGrid {
  GridView grid;
  StepParams step;

  ROMP_HD void operator()(Index n) const {
    const float mass = grid.mass[n];
    if (mass <= 0.0f) return;  // velocity stays 0: no particle reads a massless node with weight > 0
    const float inverse_mass = 1.0f / mass;
    Vec3<float> v = grid.velocity.load(n) * inverse_mass;
    if (grid.keeps_old_velocity()) grid.velocity_old.store(n, grid.velocity_old.load(n) * inverse_mass);
    v += step.dt * step.gravity;

    const std::uint64_t key = grid.table.block_keys[n / kNodesPerBlock];
    const int local = int(n % kNodesPerBlock);
    const int node[3] = {block_coordinate(key, 0) * kBlockSide + local / (kBlockSide * kBlockSide),
                         block_coordinate(key, 1) * kBlockSide + local / kBlockSide % kBlockSide,
                         block_coordinate(key, 2) * kBlockSide + local % kBlockSide};

    const Vec3<float> at_rest = Vec3<float>::zero();
    for (int a = 0; a < 3; ++a) {
      if (node[a] < step.wall_cells)
        v = resolve_contact(v, at_rest, Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
      if (node[a] > step.domain_cells[a] - step.wall_cells)
        v = resolve_contact(v, at_rest, -Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
    }
    const Vec3<float> x(node[0] * grid.dx, node[1] * grid.dx, node[2] * grid.dx);
    for (Index c = 0; c < step.colliders.size(); ++c) {
      const ColliderState& collider = step.colliders[c];
      const SignedDistance sd = signed_distance(collider, x);
      if (sd.distance < 0.0f)
        v = resolve_contact(v, collider.velocity_at(x), sd.normal, collider.contact, collider.friction);
    }

    if (!is_finite(v)) atomic_min(&step.first_failure[int(Stage::GridUpdate)], std::int64_t(n));
    grid.velocity.store(n, v);
  }
};

}  // namespace

void update_grid(const Exec& exec, const GridView& grid, const StepParams& step) {
  for_each(exec, grid.blocks * kNodesPerBlock, UpdateGrid{grid, step});
}

}  // namespace romp::mpm
