// Eulerian quadrature points (ROM paper, Alg. 4) against a nonlinear reference map in double: the
// inversion of g finds the reference position to its tolerance from a first guess linearised nearby and
// from poor Jacobian estimates too, the kinematics there are the evaluator's, and points outside the body
// are dropped. Runs on the test backend.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <random>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/rom/deformation_map_eval.h"
#include "kernels/rom/eulerian_quadrature.h"
#include "tests/kernels/rom/reference_map.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

constexpr int kLatent = 6;
constexpr float kTolerance = 2e-6f;  // m, on |g(X) − x|
constexpr float kVolume = 1e-6f;

// The reference body: the map's box [-0.1, 0.2] × [0.2, 0.6] × [0.05, 0.25] m in cells of 2 cm, material 0
// below X = 0.06 m and material 1 from there.
struct Body {
  static constexpr float kH = 0.02f;
  int cells[3] = {15, 20, 10};
  DeviceBuffer<std::int32_t> material_plus_one;
  ReferenceOccupancy occupancy;
  DeviceBuffer<float> density;

  Body() {
    std::vector<std::int32_t> cell_material;
    for (int k = 0; k < cells[2]; ++k)
      for (int j = 0; j < cells[1]; ++j)
        for (int i = 0; i < cells[0]; ++i) cell_material.push_back(i < 8 ? 1 : 2);
    const Exec& exec = test::exec();
    material_plus_one = DeviceBuffer<std::int32_t>::from_host(exec.backend, cell_material, exec.stream);
    density = DeviceBuffer<float>::from_host(exec.backend, std::vector<float>{1000.0f, 500.0f}, exec.stream);
    occupancy.origin = Vec3<float>(-0.1f, 0.2f, 0.05f);
    occupancy.inverse_h = 1.0f / kH;
    for (int a = 0; a < 3; ++a) occupancy.cells[a] = cells[a];
    occupancy.material_plus_one = Span<const std::int32_t>(material_plus_one.data(), material_plus_one.size());
  }
};

// Reference positions near cell centres (within 0.3 cells), so the material lookup is unambiguous.
std::vector<Eigen::Vector3d> points_inside(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> cell_x(0, 14), cell_y(0, 19), cell_z(0, 9);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d cell(cell_x(random), cell_y(random), cell_z(random));
    const Eigen::Vector3d offset(jitter(random), jitter(random), jitter(random));
    points.push_back(Eigen::Vector3d(-0.1, 0.2, 0.05) + (cell + Eigen::Vector3d::Constant(0.5) + offset) * Body::kH);
  }
  return points;
}

std::vector<float> planes(const std::vector<Eigen::Vector3d>& points) {
  const std::size_t n = points.size();
  std::vector<float> values(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) values[a * n + i] = float(points[i](a));
  return values;
}

struct Quadrature {
  std::vector<float> X, v, F, mass, volume0, F_map, dg_map;
  std::vector<std::int32_t> material, status, iterations, evaluations, jacobian_evaluations;
  QuadratureTally tally;
};

// The random map with displacements scaled up, so that g is far from linear over a few centimetres.
ReferenceMap strongly_nonlinear_map(int hidden, int width) {
  ReferenceMap map = random_map(kLatent, hidden, width, 11);
  map.u_std *= 2.5;
  return map;
}

// A map of `Hidden` layers of `Width` units: the papers' 5 × 30 runs the fixed-shape kernel, other sizes
// the generic one.
template <int Hidden, int Width>
class QuadratureFixture : public ::testing::Test {
 protected:
  const ReferenceMap reference = strongly_nonlinear_map(Hidden, Width);
  const UploadedMap<float> map = upload<float>(test::exec(), reference, Hidden, Width);
  const Eigen::VectorXd xhat = Eigen::VectorXd::LinSpaced(kLatent, -0.6, 0.9);
  const Eigen::VectorXd vhat = Eigen::VectorXd::LinSpaced(kLatent, 0.3, -0.2);
  Body body;

  std::vector<float> latent(const Eigen::VectorXd& values) const {
    return std::vector<float>(values.data(), values.data() + values.size());
  }

  // g, ∇_X g and ∂g/∂x̂ from the fused evaluator at `points` (planes).
  void evaluate(const std::vector<float>& points, std::vector<float>& x, std::vector<float>& F,
                std::vector<float>& dg) const {
    const Exec& exec = test::exec();
    const Index n = Index(points.size() / 3);
    const auto X = DeviceBuffer<float>::from_host(exec.backend, points, exec.stream);
    const auto xhat_buffer = DeviceBuffer<float>::from_host(exec.backend, latent(xhat), exec.stream);
    DeviceBuffer<float> x_out(exec.backend, 3 * n), F_out(exec.backend, 9 * n), dg_out(exec.backend, 3 * kLatent * n);
    evaluate_deformation_map<float>(
        exec, map.view, xhat_buffer.span(), Vec3Planes<const float>(X.data(), n),
        {Vec3Planes<float>(x_out.data(), n), Mat3Planes<float>(F_out.data(), n), dg_out.span()});
    x = x_out.to_host(exec.stream);
    F = F_out.to_host(exec.stream);
    dg = dg_out.to_host(exec.stream);
  }

  // Runs the quadrature at the current positions of `truth` (g in double), from `X_guess` and
  // `F_guess` (planes), then evaluates the map at the points it returned.
  Quadrature run(const std::vector<Eigen::Vector3d>& truth, const std::vector<float>& X_guess,
                 const std::vector<float>& F_guess, int iterations = 20, MapKernel kernel = MapKernel::Fastest,
                 int predicted_margin = InversionOptions{}.predicted_margin) const {
    const Exec& exec = test::exec();
    const Index n = Index(truth.size());
    std::vector<Eigen::Vector3d> current;
    for (const Eigen::Vector3d& X : truth) current.push_back(reference.g(xhat, X));
    const auto x = DeviceBuffer<float>::from_host(exec.backend, planes(current), exec.stream);
    const auto guess = DeviceBuffer<float>::from_host(exec.backend, X_guess, exec.stream);
    const auto guess_F = DeviceBuffer<float>::from_host(exec.backend, F_guess, exec.stream);
    const auto xhat_buffer = DeviceBuffer<float>::from_host(exec.backend, latent(xhat), exec.stream);
    const auto vhat_buffer = DeviceBuffer<float>::from_host(exec.backend, latent(vhat), exec.stream);
    DeviceBuffer<float> X(exec.backend, 3 * n), v(exec.backend, 3 * n), F(exec.backend, 9 * n), mass(exec.backend, n),
        volume0(exec.backend, n);
    DeviceBuffer<std::int32_t> material(exec.backend, n), status(exec.backend, n), steps(exec.backend, n),
        evaluations(exec.backend, n), jacobian_evaluations(exec.backend, n);
    DeviceBuffer<QuadratureTally> tally(exec.backend, 1);
    tally.fill_zero(exec.stream);
    InversionOptions options;
    options.iterations = iterations;
    options.tolerance = kTolerance;
    options.predicted_margin = predicted_margin;
    const EulerianPointsOut out{Vec3Planes<float>(X.data(), n),
                                Vec3Planes<float>(v.data(), n),
                                Mat3Planes<float>(F.data(), n),
                                mass.span(),
                                volume0.span(),
                                material.span(),
                                status.span(),
                                steps.span(),
                                evaluations.span(),
                                jacobian_evaluations.span()};
    eulerian_quadrature(exec, map.view, xhat_buffer.span(), vhat_buffer.span(), body.occupancy, body.density.span(),
                        kVolume, options, Vec3Planes<const float>(x.data(), n),
                        Vec3Planes<const float>(guess.data(), n), Mat3Planes<const float>(guess_F.data(), n), out,
                        kernel);
    tally_quadrature(exec, out, n, tally.span());
    Quadrature q{X.to_host(exec.stream),
                 v.to_host(exec.stream),
                 F.to_host(exec.stream),
                 mass.to_host(exec.stream),
                 volume0.to_host(exec.stream),
                 {},
                 {},
                 material.to_host(exec.stream),
                 status.to_host(exec.stream),
                 steps.to_host(exec.stream),
                 evaluations.to_host(exec.stream),
                 jacobian_evaluations.to_host(exec.stream),
                 tally.to_host(exec.stream)[0]};
    std::vector<float> x_map;
    evaluate(q.X, x_map, q.F_map, q.dg_map);
    return q;
  }

  // First guesses as the host makes them: g linearised at a point up to 6 cm from each (per axis).
  void linearised_guesses(const std::vector<Eigen::Vector3d>& truth, std::vector<float>& X_guess,
                          std::vector<float>& F_guess) const {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> offset(-0.06, 0.06);
    std::vector<Eigen::Vector3d> nearby;
    for (const Eigen::Vector3d& X : truth)
      nearby.push_back(X + Eigen::Vector3d(offset(random), offset(random), offset(random)));
    std::vector<float> x_near, dg;
    evaluate(planes(nearby), x_near, F_guess, dg);
    const std::size_t n = truth.size();
    X_guess.assign(3 * n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Matrix3d F;
      Eigen::Vector3d x_s;
      for (int r = 0; r < 3; ++r) {
        x_s(r) = x_near[r * n + i];
        for (int c = 0; c < 3; ++c) F(r, c) = F_guess[(3 * r + c) * n + i];
      }
      const Eigen::Vector3d guess = nearby[i] + F.inverse() * (reference.g(xhat, truth[i]) - x_s);
      for (int a = 0; a < 3; ++a) X_guess[a * n + i] = float(guess(a));
    }
  }

  // Every point found to its tolerance, with the kinematics of the evaluator there and its material's mass.
  void expect_found(const std::vector<Eigen::Vector3d>& truth, const Quadrature& q) const {
    const std::size_t n = truth.size();
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(q.status[i], kQuadratureUsed) << "point " << i;
      Eigen::Matrix3d F;
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(q.X[a * n + i], truth[i](a), 1e-5) << "point " << i;
        float velocity = 0.0f;
        for (int j = 0; j < kLatent; ++j) velocity += q.dg_map[(a * kLatent + j) * n + i] * float(vhat(j));
        EXPECT_NEAR(q.v[a * n + i], velocity, 1e-5f) << "point " << i;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(q.F[(3 * a + c) * n + i], q.F_map[(3 * a + c) * n + i], 1e-5f) << "point " << i;
          F(a, c) = q.F_map[(3 * a + c) * n + i];
        }
      }
      const int material = truth[i](0) < 0.06 ? 0 : 1;
      EXPECT_EQ(q.material[i], material) << "point " << i;
      EXPECT_NEAR(q.volume0[i], kVolume / F.determinant(), 1e-5 * kVolume) << "point " << i;
      EXPECT_NEAR(q.mass[i], (material == 0 ? 1000.0 : 500.0) * kVolume / F.determinant(), 1e-5 * 1000.0 * kVolume);
    }
  }
};

class EulerianQuadrature : public QuadratureFixture<3, 16> {};
class EulerianQuadraturePaperMap : public QuadratureFixture<5, 30> {};

TEST_F(EulerianQuadrature, FindsTheReferencePositionFromALinearisedGuess) {
  const std::vector<Eigen::Vector3d> truth = points_inside(200, 1);
  std::vector<float> X_guess, F_guess;
  linearised_guesses(truth, X_guess, F_guess);
  const Quadrature q = run(truth, X_guess, F_guess);
  expect_found(truth, q);
  double iterations = 0.0;
  for (std::int32_t steps : q.iterations) iterations += steps;
  EXPECT_LT(iterations / double(truth.size()), 2.0);
}

TEST_F(EulerianQuadrature, ConvergesFromPoorOrUnusableJacobianEstimates) {
  const std::vector<Eigen::Vector3d> truth = points_inside(100, 2);
  const std::size_t n = truth.size();
  std::vector<float> X_guess = planes(truth);
  for (std::size_t i = 0; i < n; ++i) X_guess[i] += 0.01f;
  // Twice the identity: its steps are half as long as they should be, so without Broyden's updates
  // (a chord method) the error would only halve per iteration, about 13 iterations to the tolerance.
  // Then the negated identity, which has no usable inverse (det < 0): the first step is Newton's.
  for (const float scale : {2.0f, -1.0f}) {
    std::vector<float> F_guess(9 * n, 0.0f);
    for (int d = 0; d < 3; ++d) std::fill_n(F_guess.begin() + (4 * d) * n, n, scale);
    SCOPED_TRACE(scale);
    const Quadrature q = run(truth, X_guess, F_guess);
    expect_found(truth, q);
    EXPECT_LE(*std::max_element(q.iterations.begin(), q.iterations.end()), 8);
  }
}

TEST_F(EulerianQuadrature, DropsPointsOutsideTheBodyAndThoseItCannotInvert) {
  // Half a cell beyond the body's faces (inverted, then found outside), and ten cells beyond (dropped
  // without inverting: the guess lies past the margin).
  const std::vector<Eigen::Vector3d> truth = {
      {-0.11, 0.4, 0.15}, {0.21, 0.4, 0.15}, {0.05, 0.61, 0.15}, {0.05, 0.4, -0.15}};
  const std::size_t n = truth.size();
  std::vector<float> X_guess = planes(truth), F_guess(9 * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) X_guess[n + i] += 0.002f;  // so that the near points need steps
  for (int d = 0; d < 3; ++d) std::fill_n(F_guess.begin() + (4 * d) * n, n, 1.0f);
  const Quadrature q = run(truth, X_guess, F_guess);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(q.status[i], kQuadratureOutside) << "point " << i;
    EXPECT_EQ(q.mass[i], 0.0f);
    EXPECT_EQ(q.volume0[i], 0.0f);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(q.v[a * n + i], 0.0f);
    for (int e = 0; e < 9; ++e) EXPECT_EQ(q.F[e * n + i], e % 4 == 0 ? 1.0f : 0.0f);
  }
  EXPECT_GT(q.iterations[0], 0);
  EXPECT_EQ(q.iterations[3], 0);

  // One iteration from a guess 1 cm off leaves the residual above the tolerance: unconverged, dropped.
  const std::vector<Eigen::Vector3d> inside = points_inside(1, 3);
  std::vector<float> off = planes(inside), identity(9, 0.0f);
  off[0] += 0.01f;
  identity[0] = identity[4] = identity[8] = 1.0f;
  const Quadrature stopped = run(inside, off, identity, 1);
  EXPECT_EQ(stopped.status[0], kQuadratureUnconverged);
  EXPECT_EQ(stopped.mass[0], 0.0f);
}

// A point whose first quasi-Newton step ends more than predicted_margin cells from any material lands
// outside the body: it is dropped after the one evaluation at its guess, where iterating to the solution
// took more and found it outside all the same. Points inside are found as before.
TEST_F(EulerianQuadrature, DropsAPointWhoseFirstStepEndsFarOutsideTheBody) {
  // Solutions 2 and 3 cells beyond the face X = −0.1 m, guesses 1.25 cells beyond it (within the guesses'
  // margin of 2 cells, so they are inverted).
  const std::vector<Eigen::Vector3d> truth = {{-0.14, 0.41, 0.15}, {-0.16, 0.33, 0.11}};
  const std::size_t n = truth.size();
  std::vector<float> X_guess = planes(truth), F_guess;
  for (std::size_t i = 0; i < n; ++i) X_guess[i] = -0.125f;
  std::vector<float> x_guess, dg;
  evaluate(X_guess, x_guess, F_guess, dg);  // ∇_X g at the guesses: the first step is Newton's
  const Quadrature early = run(truth, X_guess, F_guess);
  const Quadrature late = run(truth, X_guess, F_guess, 20, MapKernel::Fastest, /*predicted_margin=*/1000);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(early.status[i], kQuadratureOutside) << "point " << i;
    EXPECT_EQ(late.status[i], kQuadratureOutside) << "point " << i;
    EXPECT_EQ(early.evaluations[i], 1) << "point " << i;
    EXPECT_GE(late.evaluations[i], 2) << "point " << i;
    EXPECT_EQ(early.mass[i], 0.0f);
  }
  // Inside the body the early drop changes nothing.
  const std::vector<Eigen::Vector3d> inside = points_inside(100, 6);
  std::vector<float> inside_guess, inside_F;
  linearised_guesses(inside, inside_guess, inside_F);
  const Quadrature with = run(inside, inside_guess, inside_F);
  const Quadrature without = run(inside, inside_guess, inside_F, 20, MapKernel::Fastest, 1000);
  expect_found(inside, with);
  EXPECT_EQ(with.X, without.X);
  EXPECT_EQ(with.evaluations, without.evaluations);
}

// The fixed-shape kernel on the papers' network: every point found, and the same points, positions and
// kinematics as the generic kernel (the same iteration; the map's rounding differs).
TEST_F(EulerianQuadraturePaperMap, FixedShapeKernelFindsWhatTheGenericOneFinds) {
  const std::vector<Eigen::Vector3d> truth = points_inside(200, 1);
  std::vector<float> X_guess, F_guess;
  linearised_guesses(truth, X_guess, F_guess);
  const Quadrature fixed = run(truth, X_guess, F_guess, 20, MapKernel::Fixed);
  const Quadrature generic = run(truth, X_guess, F_guess, 20, MapKernel::Generic);
  expect_found(truth, fixed);
  EXPECT_EQ(fixed.status, generic.status);
  EXPECT_EQ(fixed.material, generic.material);
  for (std::size_t k = 0; k < fixed.X.size(); ++k) {
    EXPECT_NEAR(fixed.X[k], generic.X[k], 1e-5f) << k;
    EXPECT_NEAR(fixed.v[k], generic.v[k], 1e-5f) << k;
  }
  for (std::size_t k = 0; k < fixed.F.size(); ++k) EXPECT_NEAR(fixed.F[k], generic.F[k], 1e-5f) << k;
  for (std::size_t i = 0; i < fixed.mass.size(); ++i)
    EXPECT_NEAR(fixed.mass[i], generic.mass[i], 1e-5f * 1000.0f * kVolume);
}

// The inversion's cost as the kernel counts it: a point whose guess is its solution takes the evaluation
// at the guess and the kinematics' (the only one with the Jacobians); a point dropped before inverting
// takes none; one found outside the body takes no kinematics. The tally sums the points' counts.
TEST_F(EulerianQuadrature, CountsItsEvaluationsOfTheMapAndTalliesThem) {
  const std::vector<Eigen::Vector3d> truth = points_inside(60, 4);
  const std::size_t n = truth.size();
  std::vector<float> X_guess, F_guess;
  linearised_guesses(truth, X_guess, F_guess);
  const Quadrature q = run(truth, X_guess, F_guess);
  expect_found(truth, q);
  std::int64_t sums[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    // Start, at least one trial per iteration, the kinematics.
    EXPECT_GE(q.evaluations[i], 2 + q.iterations[i]) << "point " << i;
    EXPECT_GE(q.jacobian_evaluations[i], 1) << "point " << i;
    EXPECT_LT(q.jacobian_evaluations[i], q.evaluations[i]) << "point " << i;
    sums[0] += q.iterations[i];
    sums[1] += q.evaluations[i];
    sums[2] += q.jacobian_evaluations[i];
  }
  EXPECT_EQ(q.tally.points[kQuadratureUsed], std::int64_t(n));
  EXPECT_EQ(q.tally.points[kQuadratureOutside] + q.tally.points[kQuadratureUnconverged], 0);
  EXPECT_EQ(q.tally.iterations, sums[0]);
  EXPECT_EQ(q.tally.evaluations, sums[1]);
  EXPECT_EQ(q.tally.jacobian_evaluations, sums[2]);
  double mass = 0.0;
  for (float m : q.mass) mass += m;
  EXPECT_NEAR(q.tally.last_mass, mass, 1e-6 * mass);

  // Guesses at the solutions themselves (the inverse the run found): nothing to iterate.
  const Quadrature exact = run(truth, q.X, F_guess);
  for (std::size_t i = 0; i < n; ++i) {
    if (exact.iterations[i] != 0) continue;  // float rounding can leave a residual above the tolerance
    EXPECT_EQ(exact.evaluations[i], 2) << "point " << i;
    EXPECT_EQ(exact.jacobian_evaluations[i], 1) << "point " << i;
  }
  EXPECT_GT(std::count(exact.iterations.begin(), exact.iterations.end(), 0), std::ptrdiff_t(n / 2));

  // Ten cells beyond the body: dropped at the guess, no evaluation at all; half a cell beyond: inverted,
  // found outside, no kinematics.
  const std::vector<Eigen::Vector3d> outside = {{-0.11, 0.4, 0.15}, {0.05, 0.4, -0.15}};
  std::vector<float> outside_guess = planes(outside), identity(9 * outside.size(), 0.0f);
  for (int d = 0; d < 3; ++d) std::fill_n(identity.begin() + (4 * d) * outside.size(), outside.size(), 1.0f);
  const Quadrature dropped = run(outside, outside_guess, identity);
  EXPECT_GE(dropped.evaluations[0], 1);
  EXPECT_EQ(dropped.jacobian_evaluations[0], 0);
  EXPECT_EQ(dropped.evaluations[1], 0);
  EXPECT_EQ(dropped.tally.points[kQuadratureOutside], 2);
  EXPECT_EQ(dropped.tally.last_mass, 0.0);
}

}  // namespace
}  // namespace romp::rom
