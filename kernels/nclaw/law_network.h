// One particle of a neural constitutive law (Ma et al. 2023, Alg. 4), forward and backward, in one function
// each: the SVD of F, the 13 invariant features, the bias-free 13 → 64 → 64 → 9 GELU network, the
// symmetrised output rotated back, and the plastic law's F + α R T.
//
// Why fused. Op by op (LibTorch) a law is ~40 launches per substep, each over 1,000 particles: on the
// H200 the GPU idled between them (81 % of the pool scene's run time, a training epoch slower than this
// 2-core CPU). Per particle the whole law is ~5,500 multiply-adds forward and ~15,000 backward (the
// forward recomputed) on 13 inputs and 9 outputs, so one thread per particle does it with nothing in
// memory but F, the output and the weights (22 KB, read by every thread of a warp at the same address: one
// broadcast load each). This is the CUDA path; the host runs law_lanes.h, which shares its per-particle
// pieces (SVD, features, output and their backward passes) and takes the network layer by layer.
//
// Register layout. The layer sizes are compile-time constants and every loop that indexes an activation
// array is unrolled on the device (ROMP_UNROLL), so the 64 hidden activations (and, backward, their 64
// gradients) live in registers; the loop over the second hidden layer's units streams one unit at a time
// (its pre-activation, GELU, output contribution) and stays rolled. The backward pass recomputes the
// forward activations from F instead of storing them (~1/3 more arithmetic, no activation traffic).
//
// Conventions are those of the law composed of LibTorch operators (nn/nclaw/composed_law.h): features
// σ − 1, FᵀF − I (row-major), det F − 1 with det F the triple product of F's rows; GELU the exact erf
// form (torch::gelu's default); weights row-major [outputs, inputs] as torch::nn::Linear holds them.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/exp_erf.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"
#include "kernels/svd/svd3.h"
#include "kernels/svd/svd3_backward.h"

namespace romp::nclaw {

inline constexpr int kLawInputs = 13;  // σ − 1 (3), FᵀF − I (9), det F − 1 (1)
inline constexpr int kLawWidth = 64;   // hidden width of both laws (App. D.2)
inline constexpr int kLawOutputs = 9;  // a 3×3 matrix, symmetrised
inline constexpr int kLawWeights = kLawWidth * kLawInputs + kLawWidth * kLawWidth + kLawOutputs * kLawWidth;

// The three weight matrices of one network, row-major [outputs, inputs].
template <class T>
struct LawWeights {
  const T* input = nullptr;   // [64, 13]
  const T* hidden = nullptr;  // [64, 64]
  const T* output = nullptr;  // [9, 64]
};

// What a law returns from Y = R sym(MLP(features)): the elastic law P = Y (scale 1, no input), the
// plastic law F_new = F + α Y (scale α, the input added).
template <class T>
struct LawOutput {
  T scale = T(1);
  bool adds_input = false;
};

// Per-particle rows the weight gradients are sums over: dW_input = Σ ds1 ⊗ features, dW_hidden = Σ ds2 ⊗
// h1, dW_output = Σ dout ⊗ h2 (pre-activation gradients ds, activations h). They lie in planes, one per
// entry, `stride` (the particle count) scalars each, in this order; each pointer is particle i's entry of
// its first plane, so the per-thread writes coalesce.
inline constexpr int kLawActivationPlanes = kLawInputs + 4 * kLawWidth + kLawOutputs;

template <class T>
struct LawActivationRows {
  T* features;         // 13
  T* input_gradient;   // ds1, 64
  T* hidden;           // h1, 64
  T* hidden_gradient;  // ds2, 64
  T* last;             // h2, 64
  T* output_gradient;  // dout, 9
  Index stride;
};

// Particle i's rows in scratch of kLawActivationPlanes × count scalars.
template <class T>
ROMP_MATH_INLINE LawActivationRows<T> activation_rows(T* scratch, Index count, Index i) {
  LawActivationRows<T> rows;
  rows.features = scratch + i;
  rows.input_gradient = rows.features + kLawInputs * count;
  rows.hidden = rows.input_gradient + kLawWidth * count;
  rows.hidden_gradient = rows.hidden + kLawWidth * count;
  rows.last = rows.hidden_gradient + kLawWidth * count;
  rows.output_gradient = rows.last + kLawWidth * count;
  rows.stride = count;
  return rows;
}

namespace law_detail {

template <class T>
ROMP_MATH_INLINE T gelu(T x) {
  return T(0.5) * x * (T(1) + math::erf(x * T(0.70710678118654752440)));
}

// d gelu / dx = Φ(x) + x φ(x).
template <class T>
ROMP_MATH_INLINE T gelu_slope(T x) {
  const T cdf = T(0.5) * (T(1) + math::erf(x * T(0.70710678118654752440)));
  return cdf + x * T(0.39894228040143267794) * math::exp(T(-0.5) * x * x);
}

// σ and R of F, as the reference's StretchRotationFunction gives them: a positive diagonal F (above all
// the rest state F = I) has the exact σ = its diagonal sorted and R = I, which the SVD meets only to a
// few ulps; the laws are stress-free at rest only if σ − 1 is exactly 0 there.
template <class T>
struct Stretch {
  Vec3<T> sigma;
  Mat3<T> R;
};

// Branch-free (selects, not branches), so that the host's SIMD loop over particles stays vectorised.
template <class T>
ROMP_MATH_INLINE Stretch<T> stretch_of(const Mat3<T>& F, const Svd3<T>& svd) {
  const bool diagonal = (F(0, 1) == T(0)) & (F(0, 2) == T(0)) & (F(1, 0) == T(0)) & (F(1, 2) == T(0)) &
                        (F(2, 0) == T(0)) & (F(2, 1) == T(0)) & (F(0, 0) > T(0)) & (F(1, 1) > T(0)) & (F(2, 2) > T(0));
  T a = F(0, 0), b = F(1, 1), c = F(2, 2);
  math::swap_if(a < b, a, b);
  math::swap_if(b < c, b, c);
  math::swap_if(a < b, a, b);
  Stretch<T> stretch{Vec3<T>(math::select(diagonal, a, svd.sigma[0]), math::select(diagonal, b, svd.sigma[1]),
                             math::select(diagonal, c, svd.sigma[2])),
                     times_transpose(svd.U, svd.V)};
  ROMP_UNROLL
  for (int r = 0; r < 3; ++r) ROMP_UNROLL
  for (int col = 0; col < 3; ++col) stretch.R(r, col) = math::select(diagonal, T(r == col ? 1 : 0), stretch.R(r, col));
  return stretch;
}

template <class T>
ROMP_MATH_INLINE void features_of(const Mat3<T>& F, const Vec3<T>& sigma, T (&features)[kLawInputs]) {
  const Mat3<T> cauchy_green = transpose_times(F, F) - Mat3<T>::identity();
  ROMP_UNROLL
  for (int a = 0; a < 3; ++a) features[a] = sigma[a] - T(1);
  ROMP_UNROLL
  for (int r = 0; r < 3; ++r) ROMP_UNROLL
  for (int c = 0; c < 3; ++c) features[3 + 3 * r + c] = cauchy_green(r, c);
  features[12] = determinant(F) - T(1);
}

// Pre-activations s1 = W_input · features.
template <class T>
ROMP_MATH_INLINE void first_layer(const LawWeights<T>& w, const T (&features)[kLawInputs], T (&s1)[kLawWidth]) {
  ROMP_UNROLL
  for (int k = 0; k < kLawWidth; ++k) {
    T sum = T(0);
    ROMP_UNROLL
    for (int f = 0; f < kLawInputs; ++f) sum += w.input[k * kLawInputs + f] * features[f];
    s1[k] = sum;
  }
}

// Pre-activation of hidden unit j of the second layer.
template <class T>
ROMP_MATH_INLINE T second_layer_unit(const LawWeights<T>& w, int j, const T (&h1)[kLawWidth]) {
  T sum = T(0);
  ROMP_UNROLL
  for (int k = 0; k < kLawWidth; ++k) sum += w.hidden[j * kLawWidth + k] * h1[k];
  return sum;
}

template <class T>
ROMP_MATH_INLINE Mat3<T> symmetric_output(const T (&out)[kLawOutputs]) {
  Mat3<T> T_sym;
  ROMP_UNROLL
  for (int r = 0; r < 3; ++r) ROMP_UNROLL
  for (int c = 0; c < 3; ++c) T_sym(r, c) = T(0.5) * (out[3 * r + c] + out[3 * c + r]);
  return T_sym;
}

// The law's output from the network's: scale · R sym(out), plus F for the plastic law.
template <class T>
ROMP_MATH_INLINE Mat3<T> law_output(const LawOutput<T>& output, const Mat3<T>& F, const Mat3<T>& R,
                                    const T (&out)[kLawOutputs]) {
  const Mat3<T> Y = R * symmetric_output(out);
  return output.adds_input ? F + output.scale * Y : output.scale * Y;
}

// law_output backward for dL/d(output) = dY_out: dF's direct part (the plastic law's F, and R's gradient
// scale dY Tᵀ through the polar rotation's backward pass, which has only σᵢ + σⱼ gaps), and dL/d(out),
// sym(scale Rᵀ dY) (T = sym(out) passes its gradient's symmetric part on).
template <class T>
ROMP_MATH_INLINE Mat3<T> law_output_backward(const LawOutput<T>& output, const Svd3<T>& svd, const Mat3<T>& R,
                                             const T (&out)[kLawOutputs], const Mat3<T>& dY_out,
                                             T (&dout)[kLawOutputs]) {
  const Mat3<T> dY = output.scale * dY_out;
  const Mat3<T> dT = symmetric_part(transpose_times(R, dY));
  ROMP_UNROLL
  for (int r = 0; r < 3; ++r) ROMP_UNROLL
  for (int c = 0; c < 3; ++c) dout[3 * r + c] = dT(r, c);
  const Mat3<T> dF = polar3_backward(svd, times_transpose(dY, symmetric_output(out)), Mat3<T>::zero());
  return output.adds_input ? dF + dY_out : dF;
}

// dL/dF through the features for their gradient dfeatures. FᵀF: F (G + Gᵀ); det F: ddet cof(F), whose rows
// are cross products of F's rows; σ: the SVD's backward pass (the SVD recomputed: cheaper than kept).
template <class T>
ROMP_MATH_INLINE Mat3<T> features_backward(const Mat3<T>& F, const T (&dfeatures)[kLawInputs]) {
  Mat3<T> G;
  ROMP_UNROLL
  for (int r = 0; r < 3; ++r) ROMP_UNROLL
  for (int c = 0; c < 3; ++c) G(r, c) = dfeatures[3 + 3 * r + c];
  const Vec3<T> f0 = F.row(0), f1 = F.row(1), f2 = F.row(2);
  const Mat3<T> cofactor = Mat3<T>::from_rows(cross(f1, f2), cross(f2, f0), cross(f0, f1));
  const Vec3<T> dsigma(dfeatures[0], dfeatures[1], dfeatures[2]);
  return F * (G + transpose(G)) + dfeatures[12] * cofactor +
         svd3_backward(svd3(F), Mat3<T>::zero(), dsigma, Mat3<T>::zero());
}

// The network at F: its features, h1 = gelu(W_input features) and its output `out`; where `last` is given,
// each second-layer activation h2_j also goes to last[j stride] (the backward pass keeps them for dW_output).
template <class T>
ROMP_MATH_INLINE void network_forward(const LawWeights<T>& w, const Mat3<T>& F, const Vec3<T>& sigma,
                                      T (&features)[kLawInputs], T (&h1)[kLawWidth], T (&out)[kLawOutputs], T* last,
                                      Index stride) {
  features_of(F, sigma, features);
  first_layer(w, features, h1);
  ROMP_UNROLL
  for (int k = 0; k < kLawWidth; ++k) h1[k] = gelu(h1[k]);
  ROMP_UNROLL
  for (int i = 0; i < kLawOutputs; ++i) out[i] = T(0);
  ROMP_NO_UNROLL
  for (int j = 0; j < kLawWidth; ++j) {
    const T h2 = gelu(second_layer_unit(w, j, h1));
    if (last != nullptr) last[j * stride] = h2;
    ROMP_UNROLL
    for (int i = 0; i < kLawOutputs; ++i) out[i] += w.output[i * kLawWidth + j] * h2;
  }
}

}  // namespace law_detail

// The law's output at F: scale · R sym(MLP(features(F))) (+ F for the plastic law).
template <class T>
ROMP_MATH_INLINE Mat3<T> evaluate_law(const LawWeights<T>& w, const LawOutput<T>& output, const Mat3<T>& F) {
  using namespace law_detail;
  const Stretch<T> stretch = stretch_of(F, svd3(F));
  T features[kLawInputs], h1[kLawWidth], out[kLawOutputs];
  network_forward(w, F, stretch.sigma, features, h1, out, static_cast<T*>(nullptr), 0);
  return law_output(output, F, stretch.R, out);
}

// dL/dF of the law at F for dL/d(output) = dY, writing the particle's rows of the weight gradients'
// factors to `rows` (see LawActivationRows); the weight gradients are their sums over particles.
//
// Ordered to keep few values alive at once (on the device, 255 registers hold the 64 activations and
// their 64 gradients): R's gradient is taken as soon as the output is known, the first layer's
// pre-activations and the SVD are recomputed where they are needed again instead of kept.
template <class T>
ROMP_MATH_INLINE Mat3<T> law_backward(const LawWeights<T>& w, const LawOutput<T>& output, const Mat3<T>& F,
                                      const Mat3<T>& dY, const LawActivationRows<T>& rows) {
  using namespace law_detail;
  const Index stride = rows.stride;
  T features[kLawInputs];
  T h1[kLawWidth];
  T dout[kLawOutputs];
  Mat3<T> dF;
  {
    const Svd3<T> svd = svd3(F);
    const Stretch<T> stretch = stretch_of(F, svd);
    // The output once more (its gradient needs it), with h2 kept per unit for dW_output.
    T out[kLawOutputs];
    network_forward(w, F, stretch.sigma, features, h1, out, rows.last, stride);
    dF = law_output_backward(output, svd, stretch.R, out, dY, dout);
  }
  ROMP_UNROLL
  for (int i = 0; i < kLawOutputs; ++i) rows.output_gradient[i * stride] = dout[i];

  // Second layer backward, unit by unit: ds2_j = gelu'(s2_j) Σ_i W_output[i][j] dout_i; dh1 += ds2_j W_hidden[j].
  T dh1[kLawWidth];
  ROMP_UNROLL
  for (int k = 0; k < kLawWidth; ++k) dh1[k] = T(0);
  ROMP_NO_UNROLL
  for (int j = 0; j < kLawWidth; ++j) {
    T dh2 = T(0);
    ROMP_UNROLL
    for (int i = 0; i < kLawOutputs; ++i) dh2 += w.output[i * kLawWidth + j] * dout[i];
    const T ds2 = gelu_slope(second_layer_unit(w, j, h1)) * dh2;
    rows.hidden_gradient[j * stride] = ds2;
    ROMP_UNROLL
    for (int k = 0; k < kLawWidth; ++k) dh1[k] += w.hidden[j * kLawWidth + k] * ds2;
  }

  // First layer backward: ds1 = gelu'(s1) dh1, dfeatures = W_inputᵀ ds1.
  T dfeatures[kLawInputs] = {};
  ROMP_UNROLL
  for (int k = 0; k < kLawWidth; ++k) {
    T s1 = T(0);
    ROMP_UNROLL
    for (int f = 0; f < kLawInputs; ++f) s1 += w.input[k * kLawInputs + f] * features[f];
    const T ds1 = gelu_slope(s1) * dh1[k];
    rows.hidden[k * stride] = h1[k];
    rows.input_gradient[k * stride] = ds1;
    ROMP_UNROLL
    for (int f = 0; f < kLawInputs; ++f) dfeatures[f] += w.input[k * kLawInputs + f] * ds1;
  }
  ROMP_UNROLL
  for (int f = 0; f < kLawInputs; ++f) rows.features[f * stride] = features[f];
  return dF + features_backward(F, dfeatures);
}

}  // namespace romp::nclaw
