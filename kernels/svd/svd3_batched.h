// Batched 3x3 SVD, polar decomposition and their backward passes over structure-of-arrays planes, on either backend.
//
// Every view holds `count` elements in the engine's component-major planes (Mat3Planes: nine planes,
// Vec3Planes: three); all views of one call must have the same count and live on exec's backend.
// Outputs must not alias inputs. Work is queued on exec (asynchronous on CUDA, like for_each).
// Overloads exist for float and double, so callers compiled as plain C++ (nn/) link against the
// instances built in svd3_batched.cu.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/math/mat3_planes.h"

namespace romp {

// F = U diag(σ) Vᵀ per element (see svd3 in svd3.h for the conventions).
void svd3_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<float> U, Vec3Planes<float> sigma,
                  Mat3Planes<float> V);
void svd3_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<double> U, Vec3Planes<double> sigma,
                  Mat3Planes<double> V);

// F = R S per element (see polar3 in svd3.h).
void polar3_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<float> R, Mat3Planes<float> S);
void polar3_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<double> R, Mat3Planes<double> S);

// dL/dF from dL/dU, dL/dσ, dL/dV at the forward result (U, σ, V) (see svd3_backward.h).
void svd3_backward_batched(const Exec& exec, Mat3Planes<const float> U, Vec3Planes<const float> sigma,
                           Mat3Planes<const float> V, Mat3Planes<const float> dU, Vec3Planes<const float> dsigma,
                           Mat3Planes<const float> dV, Mat3Planes<float> dF);
void svd3_backward_batched(const Exec& exec, Mat3Planes<const double> U, Vec3Planes<const double> sigma,
                           Mat3Planes<const double> V, Mat3Planes<const double> dU, Vec3Planes<const double> dsigma,
                           Mat3Planes<const double> dV, Mat3Planes<double> dF);

// dL/dF from dL/dR and dL/dS at F. The SVD of F is recomputed here, so a training step need only
// keep F (9 planes) for the backward pass instead of U, σ and V (21).
void polar3_backward_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<const float> dR,
                             Mat3Planes<const float> dS, Mat3Planes<float> dF);
void polar3_backward_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<const double> dR,
                             Mat3Planes<const double> dS, Mat3Planes<double> dF);

}  // namespace romp
