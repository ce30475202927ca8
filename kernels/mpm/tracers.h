// Tracers: passive points carried by the grid's velocity field, the "tracer particle technique" the ROM
// paper's super-resolution is measured against (Sec. 5.2.1, Table 4): points of a finer sampling than
// the simulation's, moved by what the coarse simulation computes without acting on it.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// After the grid update (and any implicit solve), with the same Δt as G2P: each tracer takes the
// quadratic B-spline interpolation of the node velocities, v = Σ_i w_i v_i, and moves by Δt v (the PIC
// transport of a particle that carries no mass). Nodes of blocks the material did not activate count
// as at rest, so a tracer beyond the material's reach stays where it is; tracers stay inside the
// domain's margin as particles do.
void advect_tracers(const Exec& exec, Vec3Planes<float> x, Vec3Planes<float> v, const GridView& grid,
                    const StepParams& step);

}  // namespace romp::mpm
