// Derived fields and totals of a frame, from its state.
#include "host/run/frame_outputs.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <limits>

#include "kernels/core/error.h"
#include "kernels/math/mat3.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/bspline.h"

namespace romp::run {
namespace {

Vec3<double> to_double(const Vec3<float>& v) { return Vec3<double>(v[0], v[1], v[2]); }

// σ's von Mises equivalent: √(3/2 s:s), s = σ − tr(σ)/3 I.
double von_mises(const Mat3<double>& sigma) {
  const double mean = (sigma(0, 0) + sigma(1, 1) + sigma(2, 2)) / 3.0;
  double squares = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double s = sigma(i, j) - (i == j ? mean : 0.0);
      squares += s * s;
    }
  return std::sqrt(1.5 * squares);
}

}  // namespace

FrameOutputs::FrameOutputs(io::FieldMask fields, const engine::FullOrderConfig& config,
                           const mpm::ParticleInit& particles)
    : fields_(fields),
      gravity_(config.gravity[0], config.gravity[1], config.gravity[2]),
      affine_inertia_(config.transfer == mpm::Transfer::Apic ? double(config.dx) * config.dx / mpm::kInverseInertiaScale
                                                             : 0.0),
      mass_(particles.mass),
      volume0_(particles.volume0),
      material_(particles.material) {
  for (const engine::MaterialSpec& m : config.materials) {
    materials_.push_back(m.params);
    learned_law_ |= m.params.model == material::MaterialModel::Neural;
  }
  if ((fields & io::kPlasticFields) && particles.plastic.empty())
    throw Error(
        fmt::format("output.fields {}: no particle of this run keeps a plastic state (a drucker-prager or "
                    "von-mises material, in a full-order run)",
                    fmt::join(io::field_names(fields & io::kPlasticFields), ", ")));
  if (learned_law_ && (fields & io::kDerivedFields))
    throw Error(
        fmt::format("output.fields: {} need a material's stress and energy in closed form; a learned law "
                    "(neural) has no energy and its stress is not evaluated for output: leave them out",
                    fmt::join(io::field_names(fields & io::kDerivedFields), ", ")));
}

void FrameOutputs::add_to(io::FrameData& frame) const {
  const std::size_t n = mass_.size();
  ROMP_CHECK(frame.x.size() == 3 * n && frame.v.size() == 3 * n && frame.F.size() == 9 * n,
             fmt::format("frame outputs: a frame of {} particles needs x, v and F", n));
  const bool spin = affine_inertia_ > 0.0 && frame.C.size() == 9 * n;
  const Vec3Planes<const float> xs(frame.x.data(), Index(n)), vs(frame.v.data(), Index(n));
  const Mat3Planes<const float> Fs(frame.F.data(), Index(n)), Cs(spin ? frame.C.data() : nullptr, Index(n));
  for (const io::FieldInfo& info : io::kFieldInfos)
    if (fields_ & info.bit & io::kDerivedFields) frame.field(info.bit).assign(std::size_t(info.components) * n, 0.0f);
  io::FrameTotals totals;
  double elastic = 0.0;
  Vec3<double> momentum = Vec3<double>::zero(), angular = Vec3<double>::zero();
  for (std::size_t p = 0; p < n; ++p) {
    const double m = mass_[p];
    const Vec3<double> x = to_double(xs.load(Index(p))), v = to_double(vs.load(Index(p)));
    totals.kinetic_energy += 0.5 * m * squared_norm(v);
    totals.gravitational_energy -= m * dot(gravity_, x);
    momentum += v * m;
    angular += cross(x, v) * m;
    if (spin) {
      // ε_ijk C_kj: twice the axial vector of C's skew part.
      const Mat3<float> C = Cs.load(Index(p));
      const Vec3<double> axial(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
      angular += axial * (m * affine_inertia_);
    }
    if (learned_law_) continue;
    const material::MaterialParams<float>& params = materials_[std::size_t(material_[p])];
    const Mat3<float> F = Fs.load(Index(p));
    const double psi = material::energy_density(params, F);
    elastic += volume0_[p] * psi;
    if (!(fields_ & io::kDerivedFields)) continue;
    const double J = determinant(F);
    // σ = P Fᵀ / J, in double from the model's float P.
    const Mat3<float> P = material::first_piola(params, F);
    Mat3<double> sigma;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double sum = 0.0;
        for (int k = 0; k < 3; ++k) sum += double(P(i, k)) * double(F(j, k));
        sigma(i, j) = sum / J;
      }
    if (fields_ & io::kFieldStress)
      for (int k = 0; k < 9; ++k) frame.stress[std::size_t(k) * n + p] = float(sigma(k / 3, k % 3));
    if (fields_ & io::kFieldJ) frame.J[p] = float(J);
    if (fields_ & io::kFieldVonMises) frame.von_mises[p] = float(von_mises(sigma));
    if (fields_ & io::kFieldEnergyDensity) frame.energy_density[p] = float(psi);
  }
  totals.elastic_energy = learned_law_ ? std::numeric_limits<double>::quiet_NaN() : elastic;
  for (int a = 0; a < 3; ++a) {
    totals.linear_momentum[std::size_t(a)] = momentum[a];
    totals.angular_momentum[std::size_t(a)] = angular[a];
  }
  frame.totals = totals;
}

}  // namespace romp::run
