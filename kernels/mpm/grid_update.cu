// Grid update: momentum to velocity, gravity, then domain walls and colliders.
#include "kernels/core/atomic.h"
#include "kernels/core/for_each.h"
#include "kernels/math/finite.h"
#include "kernels/mpm/grid_boundary.h"
#include "kernels/mpm/mls_transfer.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

struct UpdateGrid {
  GridView grid;
  StepParams step;

  ROMP_HD void operator()(Index n) const {
    if (!grid.holds_node(n)) return;
    const float mass = grid.mass[n];
    if (mass <= 0.0f) return;  // velocity stays 0: no particle reads a massless node with weight > 0
    const float inverse_mass = 1.0f / mass;
    if (grid.keeps_old_velocity()) grid.velocity_old.store(n, grid.velocity_old.load(n) * inverse_mass);
    const NodeVelocity<float> node(grid.velocity.load(n), inverse_mass, step.dt, step.gravity);
    const Vec3<float> v = resolve_boundaries(step, GridNode(grid, n), node.free);
    if (!is_finite(v)) atomic_min(&step.first_failure[int(Stage::GridUpdate)], std::int64_t(n));
    grid.velocity.store(n, v);
  }
};

}  // namespace

void update_grid(const Exec& exec, const GridView& grid, const StepParams& step) {
  for_each_bounded(exec, grid.blocks * kNodesPerBlock, grid.live_nodes(), UpdateGrid{grid, step});
}

}  // namespace romp::mpm
