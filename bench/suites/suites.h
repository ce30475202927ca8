// The suites romp-bench can run; each lives in its own file under bench/suites/.
#pragma once

#include "bench/harness.h"

namespace romp::bench {

void run_law_suite(Context& context);
void run_memory_suite(Context& context);
// The deformation map's value and derivatives: romp's fused kernel against LibTorch.
void run_mlp_suite(Context& context);
// One reduced substep with Lagrangian quadrature over every point against over the samples' neighbours.
void run_quadrature_suite(Context& context);
// Error against run time of every ROM configuration on a scene (needs --scene and --rom-model).
void run_rom_suite(Context& context);
// One substep's cost, full order against reduced order, at a scene's own resolution (random map).
void run_rom_cost_suite(Context& context);
// The robust-elasticity matrix: models × E × ν × scenarios × integrators × plain/enriched under a budget.
void run_stability_suite(Context& context);
void run_step_suite(Context& context);
// 3x3 SVDs per second: romp against Eigen (CPU) and cuSOLVER (GPU); needs memory first for the bandwidth fraction.
void run_svd_suite(Context& context);
// Seconds per neural-law training epoch (1000 substeps forward and backward, 1000 particles).
void run_train_suite(Context& context);

}  // namespace romp::bench
