// svd suite: 3x3 SVDs per second of romp's batched svd3<float>, beside Eigen's JacobiSVD on the CPU and
// cuSOLVER's gesvdjBatched on the GPU in the same run, and as a fraction of the copy bandwidth.
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench/suites/suites.h"
#include "bench/suites/svd_eigen_baseline.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/error.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/svd/svd3_batched.h"

#if defined(ROMP_WITH_CUDA)
#include <cusolverDn.h>

#include "kernels/core/device_timer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/memory.h"
#endif

namespace romp::bench {
namespace {

// Memory traffic of one SVD: F in (9 floats, 36 bytes), U, σ, V out (21 floats, 84 bytes).
constexpr double kBytesPerSvd = (9 + 21) * sizeof(float);

// How the memory suite names a place in its records ("cpu_threads=2", "cuda").
std::string place(const Exec& exec) { return exec.is_cuda() ? "cuda" : "cpu_threads=" + std::to_string(exec.threads); }

// Standard-normal entries: generic matrices, the inputs every solver sees most.
std::vector<float> random_planes(Index n) {
  std::mt19937 rng(2024);
  std::normal_distribution<float> normal;
  std::vector<float> planes(9 * std::size_t(n));
  for (float& x : planes) x = normal(rng);
  return planes;
}

const double* find_record(const Context& context, const std::string& key) {
  for (const auto& [name, value] : context.records())
    if (name == key) return &value;
  return nullptr;
}

#if defined(ROMP_WITH_CUDA)
void check_cusolver(cusolverStatus_t status, const char* call) {
  ROMP_CHECK(status == CUSOLVER_STATUS_SUCCESS,
             std::string(call) + " failed with cusolverStatus_t " + std::to_string(int(status)));
}

// A cuSOLVER handle on exec's stream and the gesvdj parameters (library defaults: tolerance at machine
// precision, up to 100 sweeps, sorted singular values).
class GesvdjSession {
 public:
  explicit GesvdjSession(const Exec& exec) {
    check_cusolver(cusolverDnCreate(&handle_), "cusolverDnCreate");
    check_cusolver(cusolverDnSetStream(handle_, exec.stream), "cusolverDnSetStream");
    check_cusolver(cusolverDnCreateGesvdjInfo(&parameters_), "cusolverDnCreateGesvdjInfo");
  }
  ~GesvdjSession() {
    cusolverDnDestroyGesvdjInfo(parameters_);
    cusolverDnDestroy(handle_);
  }
  GesvdjSession(const GesvdjSession&) = delete;
  GesvdjSession& operator=(const GesvdjSession&) = delete;

  cusolverDnHandle_t handle() const { return handle_; }
  gesvdjInfo_t parameters() const { return parameters_; }

 private:
  cusolverDnHandle_t handle_ = nullptr;
  gesvdjInfo_t parameters_ = nullptr;
};

// Planes to the column-major 3x3 blocks gesvdjBatched reads (lda = 3, one block after the other).
struct PackColumnMajor {
  Mat3Planes<const float> F;
  Span<float> packed;
  ROMP_HD void operator()(Index i) const {
    const Mat3<float> a = F.load(i);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) packed[9 * i + 3 * c + r] = a(r, c);
  }
};

// cuSOLVER's batched Jacobi SVD of the same matrices. gesvdjBatched overwrites its input, so each
// repeat first restores it (untimed); only the solver call is timed.
double time_cusolver(Context& context, const Exec& exec, Mat3Planes<const float> F) {
  constexpr int kSize = 3;  // m = n = lda = ldu = ldv
  const Index n = F.count();
  const int batch = int(n);  // the API's batch count is an int; romp-bench sizes stay far below
  DeviceBuffer<float> pristine(Backend::Cuda, 9 * n), A(Backend::Cuda, 9 * n), S(Backend::Cuda, 3 * n),
      U(Backend::Cuda, 9 * n), V(Backend::Cuda, 9 * n);
  DeviceBuffer<int> info(Backend::Cuda, n);
  for_each(exec, n, PackColumnMajor{F, pristine.span()});

  const GesvdjSession session(exec);
  const cusolverEigMode_t mode = CUSOLVER_EIG_MODE_VECTOR;
  int work_size = 0;
  check_cusolver(
      cusolverDnSgesvdjBatched_bufferSize(session.handle(), mode, kSize, kSize, A.data(), kSize, S.data(), U.data(),
                                          kSize, V.data(), kSize, &work_size, session.parameters(), batch),
      "cusolverDnSgesvdjBatched_bufferSize");
  DeviceBuffer<float> work(Backend::Cuda, work_size);

  Measurement measurement{"svd",
                          "cusolver_gesvdj_batched<float>",
                          "cuda",
                          0,
                          n,
                          "svd",
                          {},
                          kBytesPerSvd,
                          "library defaults: tolerance = machine precision, <= 100 sweeps"};
  DeviceTimer timer(exec);
  const Options& options = context.options();
  for (int run = 0; run < options.warmup + options.repeats; ++run) {
    memory::copy(A.data(), Backend::Cuda, pristine.data(), Backend::Cuda, A.bytes(), exec.stream);
    timer.start();
    check_cusolver(
        cusolverDnSgesvdjBatched(session.handle(), mode, kSize, kSize, A.data(), kSize, S.data(), U.data(), kSize,
                                 V.data(), kSize, work.data(), work_size, info.data(), session.parameters(), batch),
        "cusolverDnSgesvdjBatched");
    const double seconds = timer.stop();
    if (run >= options.warmup) measurement.seconds.push_back(seconds);
  }
  return context.add(std::move(measurement)).items_per_second();
}
#endif

}  // namespace

void run_svd_suite(Context& context) {
  const Index n = context.scaled(Index(1) << 20, 1024);
  const std::vector<float> host_F = random_planes(n);
  std::unique_ptr<EigenSvdBaseline> eigen;  // built at the first CPU place, reused by the others
  for (const Exec& exec : context.execs()) {
    const DeviceBuffer<float> F = DeviceBuffer<float>::from_host(exec.backend, host_F, exec.stream);
    DeviceBuffer<float> U(exec.backend, 9 * n), sigma(exec.backend, 3 * n), V(exec.backend, 9 * n);
    const Mat3Planes<const float> F_planes(F.data(), n);
    const Measurement& romp = context.time(
        "svd", "romp_svd3<float>", exec, n, "svd",
        [&] {
      svd3_batched(exec, F_planes, Mat3Planes<float>(U.data(), n), Vec3Planes<float>(sigma.data(), n),
                   Mat3Planes<float>(V.data(), n));
        },
        kBytesPerSvd);
    // Copied out: later measurements may reallocate the context's list.
    const double romp_per_second = romp.items_per_second();
    const double romp_gbps = romp.gigabytes_per_second();

    if (exec.is_cuda()) {
#if defined(ROMP_WITH_CUDA)
      context.record("svd.cuda.speedup_vs_cusolver", romp_per_second / time_cusolver(context, exec, F_planes));
#endif
    } else {
      if (!eigen) eigen = std::make_unique<EigenSvdBaseline>(host_F.data(), n);
      const double eigen_per_second =
          context
              .time(
                  "svd", "eigen_jacobi_svd<float>", exec, n, "svd", [&] { eigen->run(exec.threads); }, kBytesPerSvd,
                  "Eigen at the build's baseline ISA; romp dispatches AVX2/AVX-512 clones where the CPU has them")
              .items_per_second();
      context.record("svd." + place(exec) + ".speedup_vs_eigen", romp_per_second / eigen_per_second);
    }
    // Present when the memory suite ran first in this invocation.
    if (const double* copy_gbps = find_record(context, "memory." + place(exec) + ".copy_gbps"))
      context.record("svd." + place(exec) + ".fraction_of_copy_bandwidth", romp_gbps / *copy_gbps);
  }
}

}  // namespace romp::bench
