// Work queued on a stream that finishes late, for tests of stream ordering: what runs after it on
// the same stream must see its writes, and anything that races it (another stream, a host read
// without synchronisation) sees the old values.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp::test {

// values[i] *= factor for every i, queued on exec, after each element's thread has spun for
// `spin` iterations (on a GPU, about a microsecond per thousand), so the writes land late.
void scale_late(const Exec& exec, Span<float> values, float factor, int spin);

// A CUDA stream of its own (non-blocking: not ordered with the legacy default stream, as LibTorch's
// streams are not), or the CPU. Destroys the stream when it goes.
class StreamOfItsOwn {
 public:
  explicit StreamOfItsOwn(const Exec& exec);
  ~StreamOfItsOwn();
  StreamOfItsOwn(const StreamOfItsOwn&) = delete;
  StreamOfItsOwn& operator=(const StreamOfItsOwn&) = delete;
  const Exec& exec() const { return exec_; }

 private:
  Exec exec_;
};

}  // namespace romp::test
