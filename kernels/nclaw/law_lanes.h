// The neural law on a block of particles at once, layer by layer with the particles innermost: the host's path
// (and the reference the per-particle device path of law_network.h is tested against).
//
// Why a second loop order. One particle per SIMD lane over law_network.h's functions does not vectorise on
// the host: the compiler vectorises an outer loop only when its body is straight-line code, and the law's
// 64-unit loops stay loops there. Here each multiply-add runs over a block of kLanes particles (contiguous
// in a local array, one or two vectors wide), so every loop over lanes vectorises with no reassociation:
// each particle's sums are taken in law_network.h's order, term by term. The per-particle pieces (SVD,
// features, output, their backward passes) are law_network.h's own, called per lane.
#pragma once

#include "kernels/math/mat3_planes.h"
#include "kernels/nclaw/law_network.h"

namespace romp::nclaw {

// Particles per block: 16 floats fill one AVX-512 vector (two AVX2 ones); a block's activations (64 × 16 ×
// 4 B = 4 KB per array) stay in L1.
inline constexpr int kLanes = 16;

namespace lanes_detail {

// The law's network inputs and rotations of particles [begin, begin + count) (count ≤ kLanes; other lanes
// get zero features).
template <class T>
ROMP_MATH_INLINE void block_features(Mat3Planes<const T> F, Index begin, int count, T (&features)[kLawInputs][kLanes],
                                     T (&R)[9][kLanes]) {
  for (int f = 0; f < kLawInputs; ++f)
    for (int l = 0; l < kLanes; ++l) features[f][l] = T(0);
#pragma omp simd
  for (int l = 0; l < count; ++l) {
    const Mat3<T> F_l = F.load(begin + l);
    const law_detail::Stretch<T> stretch = law_detail::stretch_of(F_l, svd3(F_l));
    T features_l[kLawInputs];
    law_detail::features_of(F_l, stretch.sigma, features_l);
    for (int f = 0; f < kLawInputs; ++f) features[f][l] = features_l[f];
    for (int e = 0; e < 9; ++e) R[e][l] = stretch.R(e / 3, e % 3);
  }
}

// s1 = W_input features (pre-activations) for every lane.
template <class T>
ROMP_MATH_INLINE void block_first_layer(const LawWeights<T>& w, const T (&features)[kLawInputs][kLanes],
                                        T (&s1)[kLawWidth][kLanes]) {
  for (int k = 0; k < kLawWidth; ++k) {
#pragma omp simd
    for (int l = 0; l < kLanes; ++l) s1[k][l] = T(0);
    for (int f = 0; f < kLawInputs; ++f) {
      const T weight = w.input[k * kLawInputs + f];
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) s1[k][l] += weight * features[f][l];
    }
  }
}

// Hidden units of the second layer taken together: kUnits sums per pass over h1 share its loads and run side
// by side (one sum alone is a chain of 64 dependent multiply-adds); each still adds its terms in order.
inline constexpr int kUnits = 4;
static_assert(kLawWidth % kUnits == 0, "the hidden units come in groups of kUnits");

// s2 of hidden units [j, j + kUnits) for every lane.
template <class T>
ROMP_MATH_INLINE void block_second_layer_units(const LawWeights<T>& w, int j, const T (&h1)[kLawWidth][kLanes],
                                               T (&s2)[kUnits][kLanes]) {
  for (int u = 0; u < kUnits; ++u)
#pragma omp simd
    for (int l = 0; l < kLanes; ++l) s2[u][l] = T(0);
  for (int k = 0; k < kLawWidth; ++k)
    for (int u = 0; u < kUnits; ++u) {
      const T weight = w.hidden[(j + u) * kLawWidth + k];
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) s2[u][l] += weight * h1[k][l];
    }
}

template <class T>
ROMP_MATH_INLINE Mat3<T> lane_matrix(const T (&planes)[9][kLanes], int l) {
  Mat3<T> m;
  for (int e = 0; e < 9; ++e) m(e / 3, e % 3) = planes[e][l];
  return m;
}

template <class T>
ROMP_MATH_INLINE void lane_entries(const T (&planes)[kLawOutputs][kLanes], int l, T (&entries)[kLawOutputs]) {
  for (int i = 0; i < kLawOutputs; ++i) entries[i] = planes[i][l];
}

// The network for particles [begin, begin + count): features, rotations R, pre-activations s1, activations
// h1 and the output `out` of every lane; where `last` is given, each second-layer activation of lane l goes to
// last[j stride + l] (the backward pass keeps them for dW_output).
template <class T>
ROMP_MATH_INLINE void block_network_forward(const LawWeights<T>& w, Mat3Planes<const T> F, Index begin, int count,
                                            T (&features)[kLawInputs][kLanes], T (&R)[9][kLanes],
                                            T (&s1)[kLawWidth][kLanes], T (&h1)[kLawWidth][kLanes],
                                            T (&out)[kLawOutputs][kLanes], T* last, Index stride) {
  block_features(F, begin, count, features, R);
  block_first_layer(w, features, s1);
  for (int k = 0; k < kLawWidth; ++k)
#pragma omp simd
    for (int l = 0; l < kLanes; ++l) h1[k][l] = law_detail::gelu(s1[k][l]);
  for (int i = 0; i < kLawOutputs; ++i)
    for (int l = 0; l < kLanes; ++l) out[i][l] = T(0);
  for (int j = 0; j < kLawWidth; j += kUnits) {
    alignas(64) T h2[kUnits][kLanes];
    block_second_layer_units(w, j, h1, h2);
    for (int u = 0; u < kUnits; ++u) {
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) h2[u][l] = law_detail::gelu(h2[u][l]);
      if (last != nullptr)
        for (int l = 0; l < count; ++l) last[(j + u) * stride + l] = h2[u][l];
    }
    for (int i = 0; i < kLawOutputs; ++i)
      for (int u = 0; u < kUnits; ++u) {
        const T weight = w.output[i * kLawWidth + j + u];
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) out[i][l] += weight * h2[u][l];
      }
  }
}

}  // namespace lanes_detail

// The law's output for particles [begin, begin + count), count ≤ kLanes, where keep(p) holds (Y may alias F).
template <class T, class Keep>
ROMP_MATH_INLINE void evaluate_law_block(const LawWeights<T>& w, const LawOutput<T>& output, Mat3Planes<const T> F,
                                         Mat3Planes<T> Y, Index begin, int count, const Keep& keep) {
  using namespace lanes_detail;
  alignas(64) T features[kLawInputs][kLanes], R[9][kLanes], s1[kLawWidth][kLanes], h1[kLawWidth][kLanes],
      out[kLawOutputs][kLanes];
  block_network_forward(w, F, begin, count, features, R, s1, h1, out, static_cast<T*>(nullptr), 0);
#pragma omp simd
  for (int l = 0; l < count; ++l) {
    T out_l[kLawOutputs];
    lane_entries(out, l, out_l);
    const Mat3<T> Y_l = law_detail::law_output(output, F.load(begin + l), lane_matrix(R, l), out_l);
    if (keep(begin + l)) Y.store(begin + l, Y_l);
  }
}

// law_backward (law_network.h) for particles [begin, begin + count), count ≤ kLanes, into dF and the rows of
// scratch (activation_rows(scratch, F.count(), ·)).
template <class T>
ROMP_MATH_INLINE void law_backward_block(const LawWeights<T>& w, const LawOutput<T>& output, Mat3Planes<const T> F,
                                         Mat3Planes<const T> dY, Mat3Planes<T> dF, T* scratch, Index begin, int count) {
  using namespace lanes_detail;
  const LawActivationRows<T> rows = activation_rows(scratch, F.count(), begin);
  const Index stride = rows.stride;
  alignas(64) T features[kLawInputs][kLanes], R[9][kLanes], s1[kLawWidth][kLanes], h1[kLawWidth][kLanes],
      out[kLawOutputs][kLanes];
  block_network_forward(w, F, begin, count, features, R, s1, h1, out, rows.last, stride);

  alignas(64) T dout[kLawOutputs][kLanes] = {};
  alignas(64) T dF_direct[9][kLanes];
#pragma omp simd
  for (int l = 0; l < count; ++l) {
    const Mat3<T> F_l = F.load(begin + l);
    T out_l[kLawOutputs], dout_l[kLawOutputs];
    lane_entries(out, l, out_l);
    const Mat3<T> dF_l =
        law_detail::law_output_backward(output, svd3(F_l), lane_matrix(R, l), out_l, dY.load(begin + l), dout_l);
    for (int i = 0; i < kLawOutputs; ++i) dout[i][l] = dout_l[i];
    for (int e = 0; e < 9; ++e) dF_direct[e][l] = dF_l(e / 3, e % 3);
  }
  for (int i = 0; i < kLawOutputs; ++i)
    for (int l = 0; l < count; ++l) rows.output_gradient[i * stride + l] = dout[i][l];

  alignas(64) T dh1[kLawWidth][kLanes] = {};
  for (int j = 0; j < kLawWidth; j += kUnits) {
    alignas(64) T dh2[kUnits][kLanes] = {}, ds2[kUnits][kLanes];
    for (int u = 0; u < kUnits; ++u)
      for (int i = 0; i < kLawOutputs; ++i) {
        const T weight = w.output[i * kLawWidth + j + u];
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) dh2[u][l] += weight * dout[i][l];
      }
    block_second_layer_units(w, j, h1, ds2);
    for (int u = 0; u < kUnits; ++u) {
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) ds2[u][l] = law_detail::gelu_slope(ds2[u][l]) * dh2[u][l];
      for (int l = 0; l < count; ++l) rows.hidden_gradient[(j + u) * stride + l] = ds2[u][l];
    }
    for (int k = 0; k < kLawWidth; ++k)
      for (int u = 0; u < kUnits; ++u) {
        const T weight = w.hidden[(j + u) * kLawWidth + k];
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) dh1[k][l] += weight * ds2[u][l];
      }
  }

  alignas(64) T dfeatures[kLawInputs][kLanes] = {};
  for (int k = 0; k < kLawWidth; ++k) {
    alignas(64) T ds1[kLanes];
#pragma omp simd
    for (int l = 0; l < kLanes; ++l) ds1[l] = law_detail::gelu_slope(s1[k][l]) * dh1[k][l];
    for (int l = 0; l < count; ++l) {
      rows.hidden[k * stride + l] = h1[k][l];
      rows.input_gradient[k * stride + l] = ds1[l];
    }
    for (int f = 0; f < kLawInputs; ++f) {
      const T weight = w.input[k * kLawInputs + f];
#pragma omp simd
      for (int l = 0; l < kLanes; ++l) dfeatures[f][l] += weight * ds1[l];
    }
  }
  for (int f = 0; f < kLawInputs; ++f)
    for (int l = 0; l < count; ++l) rows.features[f * stride + l] = features[f][l];

#pragma omp simd
  for (int l = 0; l < count; ++l) {
    T dfeatures_l[kLawInputs];
    for (int f = 0; f < kLawInputs; ++f) dfeatures_l[f] = dfeatures[f][l];
    dF.store(begin + l, lane_matrix(dF_direct, l) + law_detail::features_backward(F.load(begin + l), dfeatures_l));
  }
}

}  // namespace romp::nclaw
