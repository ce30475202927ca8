// Batched launchers of svd3, polar3 and their backward passes: one element functor per operation, run by
// romp::simd_for_each (for_each on CUDA, SIMD chunks across elements on the CPU).
#include "kernels/svd/svd3_batched.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/core/simd_for_each.h"
#include "kernels/svd/svd3.h"
#include "kernels/svd/svd3_backward.h"

namespace romp {
namespace {

template <class T>
struct Svd3Element {
  Mat3Planes<const T> F;
  Mat3Planes<T> U;
  Vec3Planes<T> sigma;
  Mat3Planes<T> V;
  ROMP_MATH_INLINE void operator()(Index i) const {
    const Svd3<T> svd = svd3(F.load(i));
    U.store(i, svd.U);
    sigma.store(i, svd.sigma);
    V.store(i, svd.V);
  }
};

template <class T>
struct Polar3Element {
  Mat3Planes<const T> F;
  Mat3Planes<T> R;
  Mat3Planes<T> S;
  ROMP_MATH_INLINE void operator()(Index i) const {
    const Polar3<T> polar = polar3(F.load(i));
    R.store(i, polar.R);
    S.store(i, polar.S);
  }
};

template <class T>
struct Svd3BackwardElement {
  Mat3Planes<const T> U;
  Vec3Planes<const T> sigma;
  Mat3Planes<const T> V;
  Mat3Planes<const T> dU;
  Vec3Planes<const T> dsigma;
  Mat3Planes<const T> dV;
  Mat3Planes<T> dF;
  ROMP_MATH_INLINE void operator()(Index i) const {
    const Svd3<T> svd{U.load(i), sigma.load(i), V.load(i)};
    dF.store(i, svd3_backward(svd, dU.load(i), dsigma.load(i), dV.load(i)));
  }
};

template <class T>
struct Polar3BackwardElement {
  Mat3Planes<const T> F;
  Mat3Planes<const T> dR;
  Mat3Planes<const T> dS;
  Mat3Planes<T> dF;
  ROMP_MATH_INLINE void operator()(Index i) const {
    dF.store(i, polar3_backward(svd3(F.load(i)), dR.load(i), dS.load(i)));
  }
};

void check_count(const char* operation, const char* view, Index count, Index expected) {
  ROMP_CHECK(count == expected, std::string(operation) + ": " + view + " holds " + std::to_string(count) +
                                    " elements, expected " + std::to_string(expected) + " (as the first input)");
}

template <class T>
void svd3_batched_impl(const Exec& exec, Mat3Planes<const T> F, Mat3Planes<T> U, Vec3Planes<T> sigma, Mat3Planes<T> V) {
  const Index n = F.count();
  check_count("svd3_batched", "U", U.count(), n);
  check_count("svd3_batched", "sigma", sigma.count(), n);
  check_count("svd3_batched", "V", V.count(), n);
  simd_for_each(exec, n, Svd3Element<T>{F, U, sigma, V});
}

template <class T>
void polar3_batched_impl(const Exec& exec, Mat3Planes<const T> F, Mat3Planes<T> R, Mat3Planes<T> S) {
  const Index n = F.count();
  check_count("polar3_batched", "R", R.count(), n);
  check_count("polar3_batched", "S", S.count(), n);
  simd_for_each(exec, n, Polar3Element<T>{F, R, S});
}

template <class T>
void svd3_backward_batched_impl(const Exec& exec, Mat3Planes<const T> U, Vec3Planes<const T> sigma,
                                Mat3Planes<const T> V, Mat3Planes<const T> dU, Vec3Planes<const T> dsigma,
                                Mat3Planes<const T> dV, Mat3Planes<T> dF) {
  const Index n = U.count();
  check_count("svd3_backward_batched", "sigma", sigma.count(), n);
  check_count("svd3_backward_batched", "V", V.count(), n);
  check_count("svd3_backward_batched", "dU", dU.count(), n);
  check_count("svd3_backward_batched", "dsigma", dsigma.count(), n);
  check_count("svd3_backward_batched", "dV", dV.count(), n);
  check_count("svd3_backward_batched", "dF", dF.count(), n);
  simd_for_each(exec, n, Svd3BackwardElement<T>{U, sigma, V, dU, dsigma, dV, dF});
}

template <class T>
void polar3_backward_batched_impl(const Exec& exec, Mat3Planes<const T> F, Mat3Planes<const T> dR,
                                  Mat3Planes<const T> dS, Mat3Planes<T> dF) {
  const Index n = F.count();
  check_count("polar3_backward_batched", "dR", dR.count(), n);
  check_count("polar3_backward_batched", "dS", dS.count(), n);
  check_count("polar3_backward_batched", "dF", dF.count(), n);
  simd_for_each(exec, n, Polar3BackwardElement<T>{F, dR, dS, dF});
}

}  // namespace

void svd3_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<float> U, Vec3Planes<float> sigma,
                  Mat3Planes<float> V) {
  svd3_batched_impl(exec, F, U, sigma, V);
}
void svd3_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<double> U, Vec3Planes<double> sigma,
                  Mat3Planes<double> V) {
  svd3_batched_impl(exec, F, U, sigma, V);
}

void polar3_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<float> R, Mat3Planes<float> S) {
  polar3_batched_impl(exec, F, R, S);
}
void polar3_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<double> R, Mat3Planes<double> S) {
  polar3_batched_impl(exec, F, R, S);
}

void svd3_backward_batched(const Exec& exec, Mat3Planes<const float> U, Vec3Planes<const float> sigma,
                           Mat3Planes<const float> V, Mat3Planes<const float> dU, Vec3Planes<const float> dsigma,
                           Mat3Planes<const float> dV, Mat3Planes<float> dF) {
  svd3_backward_batched_impl(exec, U, sigma, V, dU, dsigma, dV, dF);
}
void svd3_backward_batched(const Exec& exec, Mat3Planes<const double> U, Vec3Planes<const double> sigma,
                           Mat3Planes<const double> V, Mat3Planes<const double> dU, Vec3Planes<const double> dsigma,
                           Mat3Planes<const double> dV, Mat3Planes<double> dF) {
  svd3_backward_batched_impl(exec, U, sigma, V, dU, dsigma, dV, dF);
}

void polar3_backward_batched(const Exec& exec, Mat3Planes<const float> F, Mat3Planes<const float> dR,
                             Mat3Planes<const float> dS, Mat3Planes<float> dF) {
  polar3_backward_batched_impl(exec, F, dR, dS, dF);
}
void polar3_backward_batched(const Exec& exec, Mat3Planes<const double> F, Mat3Planes<const double> dR,
                             Mat3Planes<const double> dS, Mat3Planes<double> dF) {
  polar3_backward_batched_impl(exec, F, dR, dS, dF);
}

}  // namespace romp
