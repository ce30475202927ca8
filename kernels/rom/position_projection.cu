// Gauss–Newton of the position projection where the samples are (see position_projection.h): one CUDA
// block, or launches with each decision read where it is.
#include "kernels/rom/position_projection.h"

#include <string>

#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/guarded_memory.h"
#include "kernels/core/memory.h"
#include "kernels/math/cholesky_solve.h"
#include "kernels/rom/map_evaluators.h"
#include "kernels/rom/normal_equation_entry.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::rom {
namespace {

// A projection's decisions, which do not depend on the map: start from the guess, take each solved
// linearisation, write the result.
struct Decisions {
  GaussNewtonStep step;
  PositionProjection p;
  bool extrapolate;

  ROMP_HD GaussNewtonState& state() const { return p.state[0]; }
  ROMP_HD Span<const float> trial() const { return Span<const float>(p.state.data()->trial, step.latent); }
  ROMP_HD void start() const {
    GaussNewtonState& s = state();
    const int r = step.latent;
    for (int j = 0; j < r; ++j) s.trial[j] = extrapolate ? 2.0f * p.history[r + j] - p.history[j] : p.latent[j];
    // One thread over the targets: m ≤ kOneBlockSamples where it matters.
    double norm2 = 0.0;
    for (Index i = 0; i < p.target.count(); ++i) {
      const Vec3<float> t = p.target.load(i);
      norm2 += double(t[0]) * t[0] + double(t[1]) * t[1] + double(t[2]) * t[2];
    }
    s.target_norm2 = norm2;
    step.start(s);
  }
  // Solves the normal equations at trial (in place) and takes them.
  ROMP_HD std::int32_t decide() const {
    const int r = step.latent;
    double* const A = p.system.data();
    double* const c = A + r * r;
    const double cost = A[r * r + r];
    if (!cholesky_solve(r, A, c)) return step.take(state(), nullptr, cost, 0.0);
    // δᵀ A δ = ‖Lᵀ δ‖², with L in A's lower triangle.
    double predicted_decrease = 0.0;
    for (int i = 0; i < r; ++i) {
      double row = 0.0;
      for (int k = i; k < r; ++k) row += A[k * r + i] * c[k];
      predicted_decrease += row * row;
    }
    return step.take(state(), c, cost, predicted_decrease);
  }
  ROMP_HD void finish() const { step.finish(state(), p.latent.data(), p.history.data()); }
};

struct Start {
  Decisions decisions;
  ROMP_HD void operator()(Index) const { decisions.start(); }
};
struct Decide {
  Decisions decisions;
  ROMP_HD void operator()(Index) const { decisions.decide(); }
};
struct Finish {
  Decisions decisions;
  ROMP_HD void operator()(Index) const { decisions.finish(); }
};

#if defined(__CUDACC__)
// A thread per sample: 128 threads at up to 255 registers each (the fixed-shape evaluator uses 254) fit
// one SM's register file.
constexpr int kBlockThreads = int(kOneBlockSamples);

// The whole projection in one block: a thread per sample to linearise, per entry of the normal
// equations to sum, and thread 0 to decide. One evaluation per thread and iteration, not a loop of
// them: the fixed-shape evaluator inside a nested loop takes ptxas over ten minutes per architecture.
template <class Map>
__global__ void __launch_bounds__(kBlockThreads) gauss_newton_block(Map map, Decisions decisions) {
  const int r = decisions.step.latent;
  const Index m = decisions.p.X.count(), entries = Index(r) * r + r + 1;
  __shared__ std::int32_t outcome;
  if (threadIdx.x == 0) {
    decisions.start();
    outcome = GaussNewtonState::kRunning;
  }
  __syncthreads();
  // Every thread reads `outcome` after the barrier that follows its write, and thread 0 writes it
  // again only two barriers later: all threads leave the loop together.
  while (outcome == GaussNewtonState::kRunning) {
    if (threadIdx.x < m) {
      // The evaluator is called on the kernel's parameter itself: a local copy of it (a MapPoint, say)
      // would put its weights in local memory.
      const Index i = threadIdx.x;
      Vec3<float> x;
      Mat3<float> F = Mat3<float>::identity();
      map(decisions.state().trial, decisions.p.X.load(i), x, F, true,
          [dg = decisions.p.dg_dxhat.data(), m, r, i](int o, int j, float value) { dg[(o * r + j) * m + i] = value; });
      decisions.p.model.store(i, x);
    }
    __syncthreads();
    for (Index e = threadIdx.x; e < entries; e += blockDim.x)
      NormalEquationEntry{r, decisions.p.dg_dxhat, decisions.p.target, Vec3Planes<const float>(decisions.p.model),
                          decisions.p.system}(e);
    __syncthreads();
    if (threadIdx.x == 0) outcome = decisions.decide();
    __syncthreads();
  }
  if (threadIdx.x == 0) decisions.finish();
}
#endif

// The projection as launches from the host, each decision read where it is: directly on the CPU for
// hyper-reduced sample counts, downloaded (a round trip) on CUDA and for larger sample sets on either
// backend alike, so the traffic counts agree.
void project_from_host(const Exec& exec, const DeformationMapView<float>& map, const Decisions& decisions) {
  const PositionProjection& p = decisions.p;
  const int r = decisions.step.latent;
  const bool read_back = exec.is_cuda() || p.X.count() > kOneBlockSamples;
  const Span<const std::int32_t> outcome(&decisions.p.state.data()->outcome, 1);
  for_each(exec, 1, Start{decisions});
  std::int32_t decided = GaussNewtonState::kRunning;
  while (decided == GaussNewtonState::kRunning) {
    evaluate_deformation_map(exec, map, decisions.trial(), p.X, {p.model, {}, p.dg_dxhat});
    normal_equations(exec, r, p.dg_dxhat, p.target, Vec3Planes<const float>(p.model), p.system);
    for_each(exec, 1, Decide{decisions});
    if (read_back) {
      decided = download(exec.backend, outcome, exec.stream)[0];
    } else {
      const memory::DeviceAccess access;
      decided = outcome[0];
    }
  }
  for_each(exec, 1, Finish{decisions});
}

}  // namespace

void project_positions(const Exec& exec, const DeformationMapView<float>& map, const GaussNewtonOptions& options,
                       bool extrapolate, const PositionProjection& projection) {
  const int r = map.latent;
  const Index m = projection.X.count();
  ROMP_CHECK(r >= 1 && r <= kMaxMapLatent,
             "the position projection takes a latent size r in [1, " + std::to_string(kMaxMapLatent) + "]");
  ROMP_CHECK(options.iterations >= 1 && options.tolerance > 0.0,
             "Gauss–Newton needs at least one iteration and a tolerance > 0");
  ROMP_CHECK(m >= 1 && projection.target.count() == m && projection.model.count() == m,
             "the projection needs target and model positions for each of its m >= 1 samples");
  ROMP_CHECK(projection.dg_dxhat.size() == 3 * r * m, "dg_dxhat must hold 3 r planes of the sample count");
  ROMP_CHECK(projection.system.size() == Index(r) * r + r + 1, "the system needs r² + r + 1 values");
  ROMP_CHECK(projection.history.size() == 2 * r, "the history holds x̂_{n−1} and x̂_n: 2 r values");
  ROMP_CHECK(projection.latent.size() == 2 * r + 1, "the latent state needs x̂, v̂ and a status: 2 r + 1 values");
  ROMP_CHECK(projection.state.size() == 1, "the projection keeps one GaussNewtonState");
  const Decisions decisions{GaussNewtonStep{r, options}, projection, extrapolate};
  if (m > kOneBlockSamples) return project_from_host(exec, map, decisions);
  if (!exec.is_cuda()) {
    // The CPU's stand-in for the one block CUDA runs: one launch, whose decisions it reads where they are.
    memory::launch_on_cpu(exec.stream, 1, [exec, map, decisions] { project_from_host(exec, map, decisions); });
    return;
  }
#if defined(__CUDACC__)
  memory::note_launch();
  with_map_evaluator(map, MapKernel::Fastest, exec.backend, [&](const auto& evaluator) {
    gauss_newton_block<<<1, kBlockThreads, 0, exec.stream>>>(evaluator, decisions);
    romp::detail::check_launch(exec);
  });
#else
  throw Error("project_positions on CUDA from a translation unit not compiled by nvcc");
#endif
}

}  // namespace romp::rom
