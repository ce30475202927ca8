// Mat3/Vec3 algebra, the SoA plane views, and the scalar helpers the single-source math relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "kernels/math/mat3.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/scalar.h"
#include "kernels/math/vec3.h"

namespace romp {
namespace {

const Mat3<double> kA(2, -1, 0, 1, 3, 4, -2, 0, 5);
const Mat3<double> kB(1, 2, 3, 0, -1, 2, 4, 1, 0);

TEST(Mat3, ProductsMatchTheirDefinitions) {
  const Mat3<double> product = kA * kB;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(product(r, c), dot(kA.row(r), kB.column(c)));
  EXPECT_EQ(transpose_times(kA, kB), transpose(kA) * kB);
  EXPECT_EQ(times_transpose(kA, kB), kA * transpose(kB));
  const Vec3<double> x(1, -2, 3);
  EXPECT_EQ(kA * x, Vec3<double>(dot(kA.row(0), x), dot(kA.row(1), x), dot(kA.row(2), x)));
}

TEST(Mat3, DeterminantTraceAndNorms) {
  EXPECT_DOUBLE_EQ(determinant(kA), 2 * (15 - 0) + 1 * (5 + 8) + 0);
  EXPECT_DOUBLE_EQ(determinant(kA * kB), determinant(kA) * determinant(kB));
  EXPECT_DOUBLE_EQ(trace(kA), 10);
  EXPECT_DOUBLE_EQ(squared_frobenius_norm(kA), inner(kA, kA));
  EXPECT_DOUBLE_EQ(max_abs(kA), 5);
  EXPECT_DOUBLE_EQ(determinant(Mat3<double>::identity()), 1);
}

TEST(Mat3, SolvesWhereTheDeterminantIsPositive) {
  ASSERT_GT(determinant(kA), 0.0);
  const Vec3<double> r(1.0, -2.0, 0.5);
  Vec3<double> x;
  ASSERT_TRUE(solve_where_positive(kA, r, x));
  const Vec3<double> back = kA * x;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(back[a], r[a], 1e-12) << a;

  // Inverted (one row negated) and singular matrices are refused, and x is left alone.
  const Vec3<double> untouched(7.0, 8.0, 9.0);
  Mat3<double> inverted = kA;
  for (int c = 0; c < 3; ++c) inverted(0, c) = -kA(0, c);
  x = untouched;
  EXPECT_FALSE(solve_where_positive(inverted, r, x));
  EXPECT_FALSE(solve_where_positive(Mat3<double>(1, 2, 3, 2, 4, 6, 0, 1, 1), r, x));
  for (int a = 0; a < 3; ++a) EXPECT_EQ(x[a], untouched[a]);
}

TEST(Mat3, ConstructorsAgree) {
  const Vec3<double> a(1, 2, 3), b(-1, 0, 2);
  EXPECT_EQ(Mat3<double>::from_rows(kA.row(0), kA.row(1), kA.row(2)), kA);
  EXPECT_EQ(Mat3<double>::from_columns(kA.column(0), kA.column(1), kA.column(2)), kA);
  EXPECT_EQ(Mat3<double>::outer(a, b) * Vec3<double>(0, 0, 1), a * b[2]);
  EXPECT_EQ(Mat3<double>::diag(a), Mat3<double>::diag(1, 2, 3));
  EXPECT_EQ(symmetric_part(kA) + skew_part(kA), kA);
  EXPECT_EQ(cross(Vec3<double>::unit(0), Vec3<double>::unit(1)), Vec3<double>::unit(2));
}

TEST(Mat3Planes, EntryRowColumnOfMatrixIIsInPlaneThreeRowPlusColumn) {
  constexpr Index n = 5;
  std::vector<float> data(9 * n);
  for (std::size_t k = 0; k < data.size(); ++k) data[k] = float(k);
  const Mat3Planes<float> planes(data.data(), n);
  const Mat3<float> a = planes.load(3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a(r, c), float((3 * r + c) * n + 3));
  planes.store(1, Mat3<float>::identity());
  EXPECT_EQ(data[0 * n + 1], 1.0f);
  EXPECT_EQ(data[1 * n + 1], 0.0f);
  EXPECT_EQ(data[4 * n + 1], 1.0f);
  const Mat3Planes<const float> read_only = planes;  // views convert to const, never back
  EXPECT_EQ(read_only.load(1), Mat3<float>::identity());
}

TEST(Vec3Planes, ComponentKOfVectorIIsInPlaneK) {
  constexpr Index n = 4;
  std::vector<double> data(3 * n, 0.0);
  const Vec3Planes<double> planes(data.data(), n);
  planes.store(2, Vec3<double>(7, 8, 9));
  EXPECT_EQ(data[2], 7);
  EXPECT_EQ(data[n + 2], 8);
  EXPECT_EQ(data[2 * n + 2], 9);
  EXPECT_EQ(planes.load(2), Vec3<double>(7, 8, 9));
}

template <class T>
class ScalarHelpers : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ScalarHelpers, Scalars);

TYPED_TEST(ScalarHelpers, HostRsqrtIsWithinFourUlpOfTheCorrectlyRoundedValue) {
  using T = TypeParam;
  const T ulp = std::numeric_limits<T>::epsilon();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> exponent(-60, 60);
  for (int i = 0; i < 100000; ++i) {
    const T x = T(std::exp2(exponent(rng)));
    const T exact = T(1) / std::sqrt(x);
    ASSERT_LE(std::abs(math::rsqrt(x) - exact), 4 * ulp * exact) << "x = " << x;
    ASSERT_LE(std::abs(math::sqrt(x) - std::sqrt(x)), 4 * ulp * std::sqrt(x)) << "x = " << x;
  }
  EXPECT_EQ(math::sqrt(T(0)), T(0));
  EXPECT_TRUE(std::isfinite(math::rsqrt(std::numeric_limits<T>::min())));
}

TYPED_TEST(ScalarHelpers, PowerOfTwoScaleIsExactAndNormalises) {
  using T = TypeParam;
  for (T x : {T(1), T(0.75), T(3), T(1e-15), T(1e15), std::numeric_limits<T>::min(), std::numeric_limits<T>::max()}) {
    const math::PowerOfTwoScale<T> scale = math::power_of_two_scale(x);
    EXPECT_EQ(scale.down * scale.up, T(1)) << x;
    EXPECT_GE(x * scale.down, T(1)) << x;
    EXPECT_LT(x * scale.down, T(4)) << x;
    EXPECT_EQ(x * scale.down * scale.up, x) << x;  // both multiplications are exact
  }
  const T denormal = std::numeric_limits<T>::denorm_min() * T(1000);
  EXPECT_GT(denormal * math::power_of_two_scale(denormal).down, T(0));
  EXPECT_EQ(T(0) * math::power_of_two_scale(T(0)).down, T(0));
}

TYPED_TEST(ScalarHelpers, SelectsAndSigns) {
  using T = TypeParam;
  EXPECT_EQ(math::select(true, T(1), T(2)), T(1));
  EXPECT_EQ(math::select(false, T(1), T(2)), T(2));
  EXPECT_EQ(math::select(true, -T(0), T(2)), T(0));
  EXPECT_TRUE(std::signbit(math::select(true, -T(0), T(2))));  // bits are kept, not arithmetic
  EXPECT_EQ(math::sign(T(0)), T(1));
  EXPECT_EQ(math::sign(T(-3)), T(-1));
  EXPECT_EQ(math::abs(T(-3)), T(3));
  EXPECT_EQ(math::min(T(2), T(-1)), T(-1));
  EXPECT_EQ(math::max(T(2), T(-1)), T(2));
  T a = 1, b = 2;
  math::swap_if(true, a, b);
  EXPECT_EQ(a, T(2));
  EXPECT_EQ(b, T(1));
}

}  // namespace
}  // namespace romp
