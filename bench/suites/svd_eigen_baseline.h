// Eigen's JacobiSVD<Matrix3f> over a batch: the CPU baseline of the svd suite (plain C++, so nvcc never parses Eigen).
#pragma once

#include <memory>

#include "kernels/core/hd.h"

namespace romp::bench {

class EigenSvdBaseline {
 public:
  // Copies the n matrices of `planes` (host memory, the engine's nine-plane layout) into Eigen matrices.
  EigenSvdBaseline(const float* planes, Index n);
  ~EigenSvdBaseline();
  EigenSvdBaseline(const EigenSvdBaseline&) = delete;
  EigenSvdBaseline& operator=(const EigenSvdBaseline&) = delete;

  // Full SVD (ComputeFullU | ComputeFullV) of every matrix, results kept, on `threads` OpenMP threads
  // (0: OpenMP's default, as romp::Exec).
  void run(int threads);

 private:
  struct Batch;
  std::unique_ptr<Batch> batch_;
};

}  // namespace romp::bench
