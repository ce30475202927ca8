// Eigen's JacobiSVD<Matrix3f> over a batch of matrices, threaded with OpenMP: the svd suite's CPU baseline.
#include "bench/suites/svd_eigen_baseline.h"

#include <omp.h>

#include <Eigen/Dense>
#include <vector>

namespace romp::bench {

struct EigenSvdBaseline::Batch {
  std::vector<Eigen::Matrix3f> F, U, V;
  std::vector<Eigen::Vector3f> sigma;
};

EigenSvdBaseline::EigenSvdBaseline(const float* planes, Index n) : batch_(std::make_unique<Batch>()) {
  batch_->F.resize(n);
  batch_->U.resize(n);
  batch_->V.resize(n);
  batch_->sigma.resize(n);
  for (Index i = 0; i < n; ++i)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) batch_->F[i](r, c) = planes[(3 * r + c) * n + i];
}

EigenSvdBaseline::~EigenSvdBaseline() = default;

void EigenSvdBaseline::run(int threads) {
  Batch& b = *batch_;
  const Index n = Index(b.F.size());
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : omp_get_max_threads())
  for (Index i = 0; i < n; ++i) {
    const Eigen::JacobiSVD<Eigen::Matrix3f> svd(b.F[i], Eigen::ComputeFullU | Eigen::ComputeFullV);
    b.U[i] = svd.matrixU();
    b.sigma[i] = svd.singularValues();
    b.V[i] = svd.matrixV();
  }
}

}  // namespace romp::bench
