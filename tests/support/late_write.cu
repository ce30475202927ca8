// Late writes and streams of their own for the stream-ordering tests (tests/support/late_write.h).
#include "tests/support/late_write.h"

#include "kernels/core/for_each.h"

#if defined(ROMP_WITH_CUDA)
#include "kernels/core/cuda_check.h"
#endif

namespace romp::test {
namespace {

struct ScaleLate {
  Span<float> values;
  float factor;
  int spin;
  ROMP_HD void operator()(Index i) const {
    // A dependent chain the compiler cannot remove, folded into the write as an exact 1.
    float delay = 0.0f;
    for (int k = 0; k < spin; ++k) delay = delay * 0.5f + 1.0f;
    values[i] *= factor * (delay > 0.0f || spin == 0 ? 1.0f : 0.0f);
  }
};

}  // namespace

void scale_late(const Exec& exec, Span<float> values, float factor, int spin) {
  for_each(exec, values.size(), ScaleLate{values, factor, spin});
}

StreamOfItsOwn::StreamOfItsOwn(const Exec& exec) : exec_(exec) {
  if (!exec.is_cuda()) return;
#if defined(ROMP_WITH_CUDA)
  cudaStream_t stream = nullptr;
  ROMP_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
  exec_.stream = stream;
#endif
}

StreamOfItsOwn::~StreamOfItsOwn() {
#if defined(ROMP_WITH_CUDA)
  if (exec_.is_cuda()) ROMP_CUDA_CHECK_NOTHROW(cudaStreamDestroy(exec_.stream));
#endif
}

}  // namespace romp::test
