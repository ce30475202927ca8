// law_forward and law_backward: on CUDA one thread per particle (law_network.h), on the host blocks of
// particles one per SIMD lane (law_lanes.h); then one loop iteration per weight-gradient entry.
#include "kernels/nclaw/neural_law.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/simd_for_each.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/nclaw/law_lanes.h"

namespace romp::nclaw {
namespace {

ROMP_HD_INLINE bool selected(const LawSelection& selection, Index p) {
  if (selection.material != nullptr && selection.material[p] != selection.material_id) return false;
  return selection.dirichlet_group == nullptr || selection.dirichlet_group[p] == mpm::kNoDirichletGroup;
}

// kSelective false: every particle, with no test per particle.
template <class T, bool kSelective>
struct LawForwardParticle {
  LawWeights<T> weights;
  LawOutput<T> output;
  Mat3Planes<const T> F;
  Mat3Planes<T> Y;
  LawSelection selection;
  ROMP_MATH_INLINE void operator()(Index p) const {
    if (!kSelective || selected(selection, p)) Y.store(p, evaluate_law(weights, output, F.load(p)));
  }
};

template <class T>
struct LawBackwardParticle {
  LawWeights<T> weights;
  LawOutput<T> output;
  Mat3Planes<const T> F, dY;
  Mat3Planes<T> dF;
  T* activations;
  ROMP_MATH_INLINE void operator()(Index p) const {
    dF.store(p, law_backward(weights, output, F.load(p), dY.load(p), activation_rows(activations, F.count(), p)));
  }
};

// Device weight gradients: entry e of the three, in the order input, hidden, output, each row-major: the sum
// over particles, in order, of (gradient plane o) × (activation plane i), one thread per entry.
template <class T>
struct WeightGradientEntry {
  const T* activations;
  Index count;
  LawGradients<T> gradients;
  ROMP_MATH_INLINE void operator()(Index e) const {
    const LawActivationRows<const T> planes = activation_rows(activations, count, 0);
    const T *gradient, *activation;
    T* out;
    if (e < kLawWidth * kLawInputs) {
      gradient = planes.input_gradient + (e / kLawInputs) * count;
      activation = planes.features + (e % kLawInputs) * count;
      out = gradients.input + e;
    } else if (e < kLawWidth * (kLawInputs + kLawWidth)) {
      const Index h = e - kLawWidth * kLawInputs;
      gradient = planes.hidden_gradient + (h / kLawWidth) * count;
      activation = planes.hidden + (h % kLawWidth) * count;
      out = gradients.hidden + h;
    } else {
      const Index o = e - kLawWidth * (kLawInputs + kLawWidth);
      gradient = planes.output_gradient + (o / kLawWidth) * count;
      activation = planes.last + (o % kLawWidth) * count;
      out = gradients.output + o;
    }
    T sum = T(0);
    for (Index p = 0; p < count; ++p) sum += gradient[p] * activation[p];
    *out = sum;
  }
};

// Host: blocks of kLanes particles (law_lanes.h), spread over exec's threads; each block's loops are compiled
// for the widest vectors the CPU has (ROMP_SIMD_CLONES).
// A block with no selected particle is skipped: particles are sorted by grid block, so a material's
// particles mostly fill whole blocks, and a law costs about its own particles' share of the run.
template <class T, bool kSelective>
ROMP_SIMD_CLONES void forward_block(const LawForwardParticle<T, kSelective>& law, Index begin, int count) {
  const auto keep = [&](Index p) { return !kSelective || selected(law.selection, p); };
  bool any = !kSelective;
  for (int l = 0; l < count && !any; ++l) any = keep(begin + l);
  if (any) evaluate_law_block(law.weights, law.output, law.F, law.Y, begin, count, keep);
}

template <class T>
ROMP_SIMD_CLONES void backward_block(const LawBackwardParticle<T>& law, Index begin, int count) {
  law_backward_block(law.weights, law.output, law.F, law.dY, law.dF, law.activations, begin, count);
}

// Host weight gradients: dW[o][i] = Σ_p A[o][p] B[i][p] by tiles of 4 × 4 entries, whose 16 sums run side by
// side in vectors of kLanes particles. A tile reads 8 planes for 16 entries (an entry at a time read 2 for 1,
// and the activations, 1.1 MB at 1,000 particles, came from beyond L2 each time: those loops were memory-bound),
// and 16 independent sums hide the multiply-add latency. Rows and columns past the matrix's edge repeat its
// last one and are not written. Each entry's sum is taken lane by lane in particle order, then over the lanes
// in order: the result does not depend on the thread count.
constexpr int kTile = 4;

template <class T>
struct GradientTile {
  const T* A;  // O planes of `count` scalars
  const T* B;  // I planes
  int O, I;
  T* dW;  // [O, I] row-major
};

template <class T>
ROMP_SIMD_CLONES void gradient_tile(const GradientTile<T>& m, Index count, int o0, int i0) {
  const T* a[kTile];
  const T* b[kTile];
  for (int r = 0; r < kTile; ++r) a[r] = m.A + Index(o0 + r < m.O ? o0 + r : m.O - 1) * count;
  for (int c = 0; c < kTile; ++c) b[c] = m.B + Index(i0 + c < m.I ? i0 + c : m.I - 1) * count;
  alignas(64) T sums[kTile][kTile][kLanes] = {};
  Index p = 0;
  for (; p + kLanes <= count; p += kLanes)
    for (int r = 0; r < kTile; ++r)
      for (int c = 0; c < kTile; ++c)
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) sums[r][c][l] += a[r][p + l] * b[c][p + l];
  for (int l = 0; p + l < count; ++l)
    for (int r = 0; r < kTile; ++r)
      for (int c = 0; c < kTile; ++c) sums[r][c][l] += a[r][p + l] * b[c][p + l];
  for (int r = 0; r < kTile && o0 + r < m.O; ++r)
    for (int c = 0; c < kTile && i0 + c < m.I; ++c) {
      T sum = T(0);
      for (int l = 0; l < kLanes; ++l) sum += sums[r][c][l];
      m.dW[(o0 + r) * m.I + i0 + c] = sum;
    }
}

template <class T>
void weight_gradients_on_host(const Exec& exec, const T* activations, Index count, const LawGradients<T>& gradients) {
  const LawActivationRows<const T> planes = activation_rows(activations, count, 0);
  const GradientTile<T> matrices[3] = {{planes.input_gradient, planes.features, kLawWidth, kLawInputs, gradients.input},
                                       {planes.hidden_gradient, planes.hidden, kLawWidth, kLawWidth, gradients.hidden},
                                       {planes.output_gradient, planes.last, kLawOutputs, kLawWidth, gradients.output}};
  const auto tiles = [](int extent) { return (extent + kTile - 1) / kTile; };
  int first_tile[4] = {0, 0, 0, 0};
  for (int m = 0; m < 3; ++m) first_tile[m + 1] = first_tile[m] + tiles(matrices[m].O) * tiles(matrices[m].I);
  detail::for_each_cpu(exec, first_tile[3], [&](Index tile) {
    const int m = tile < first_tile[1] ? 0 : tile < first_tile[2] ? 1 : 2;
    const int index = int(tile) - first_tile[m], columns = tiles(matrices[m].I);
    gradient_tile(matrices[m], count, (index / columns) * kTile, (index % columns) * kTile);
  });
}

// Threads per CUDA block of the per-particle law kernels: a training substep's thousand particles in 16
// blocks, on 16 SMs instead of 4 (the kernels are arithmetic-bound, each warp busy for ~14k instructions).
constexpr int kLawThreadsPerBlock = 64;

// `count` elements of `work`: a thread each on CUDA, blocks of kLanes on the host.
template <class Work, class Block>
void run_blocks(const Exec& exec, Index count, const Work& work, const Block& block) {
  if (exec.is_cuda()) {
    for_each<kLawThreadsPerBlock>(exec, count, work);
  } else {
    detail::for_each_chunk_cpu(exec, count, kLanes, [&](Index begin, Index lanes) { block(work, begin, int(lanes)); });
  }
}

void check_count(const char* operation, const char* view, Index count, Index expected) {
  ROMP_CHECK(count == expected, std::string(operation) + ": " + view + " holds " + std::to_string(count) +
                                    " matrices, expected " + std::to_string(expected) + " (as F)");
}

}  // namespace

template <class T>
void law_forward(const Exec& exec, const LawWeights<T>& weights, const LawOutput<T>& output, Mat3Planes<const T> F,
                 Mat3Planes<T> Y, const LawSelection& selection) {
  check_count("law_forward", "Y", Y.count(), F.count());
  if (selection.material == nullptr && selection.dirichlet_group == nullptr) {
    run_blocks(exec, F.count(), LawForwardParticle<T, false>{weights, output, F, Y, selection},
               forward_block<T, false>);
  } else {
    run_blocks(exec, F.count(), LawForwardParticle<T, true>{weights, output, F, Y, selection}, forward_block<T, true>);
  }
}

template <class T>
void law_backward(const Exec& exec, const LawWeights<T>& weights, const LawOutput<T>& output, Mat3Planes<const T> F,
                  Mat3Planes<const T> dY, Span<T> activations, const LawGradients<T>& gradients) {
  const Index n = F.count();
  check_count("law_backward", "dY", dY.count(), n);
  check_count("law_backward", "dF", gradients.F.count(), n);
  ROMP_CHECK(activations.size() == kLawActivationPlanes * n,
             "law_backward: activation scratch holds " + std::to_string(activations.size()) + " scalars, expected " +
                 std::to_string(kLawActivationPlanes * n));
  run_blocks(exec, n, LawBackwardParticle<T>{weights, output, F, dY, gradients.F, activations.data()},
             backward_block<T>);
  if (exec.is_cuda()) {
    for_each(exec, kLawWeights, WeightGradientEntry<T>{activations.data(), n, gradients});
  } else {
    weight_gradients_on_host(exec, activations.data(), n, gradients);
  }
}

#define ROMP_NEURAL_LAW(T)                                                                                   \
  template void law_forward<T>(const Exec&, const LawWeights<T>&, const LawOutput<T>&, Mat3Planes<const T>,  \
                               Mat3Planes<T>, const LawSelection&);                                          \
  template void law_backward<T>(const Exec&, const LawWeights<T>&, const LawOutput<T>&, Mat3Planes<const T>, \
                                Mat3Planes<const T>, Span<T>, const LawGradients<T>&);
ROMP_NEURAL_LAW(float)
ROMP_NEURAL_LAW(double)
#undef ROMP_NEURAL_LAW

}  // namespace romp::nclaw
