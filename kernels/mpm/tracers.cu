// Tracers: the grid's velocity interpolated at passive points, which then move with it.
#include "kernels/mpm/tracers.h"

#include "kernels/core/for_each.h"
#include "kernels/mpm/bspline.h"
#include "kernels/mpm/stencil_nodes.h"

namespace romp::mpm {
namespace {

struct AdvectTracer {
  Vec3Planes<float> x, v;
  GridView grid;
  StepParams step;

  ROMP_HD void operator()(Index t) const {
    const Vec3<float> position = x.load(t);
    const QuadraticStencil<float> stencil(position, grid.inverse_dx);
    const StencilNodes nodes(stencil, grid.table);
    Vec3<float> velocity = Vec3<float>::zero();
    for_each_stencil_offset([&](int i, int j, int k) {
      if (nodes.active(i, j, k)) velocity += stencil.weight(i, j, k) * grid.velocity.load(nodes.node(i, j, k));
    });
    v.store(t, velocity);
    x.store(t, kept_inside_domain(step.domain, position + step.dt * velocity, grid.dx));
  }
};

}  // namespace

void advect_tracers(const Exec& exec, Vec3Planes<float> x, Vec3Planes<float> v, const GridView& grid,
                    const StepParams& step) {
  for_each(exec, x.count(), AdvectTracer{x, v, grid, step});
}

}  // namespace romp::mpm
