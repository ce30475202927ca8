// Frame outputs: the derived fields of one particle against their formulas, the totals of a hand-made
// frame, and the totals of a run: energy and angular momentum (with APIC's spin term) conserved by a
// free body, and every selected field written, read back and listed in the sidecar.
#include "host/run/frame_outputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/run/scene_runner.h"
#include "host/run/simulation.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"
#include "host/scene/toml_reader.h"
#include "kernels/material/material.h"
#include "nn/io/snapshot_reader.h"
#include "tests/support/scratch_folder.h"

namespace romp::run {
namespace {

// Two particles: p0 stretched and sheared, p1 at rest, in a fixed-corotated material.
struct TwoParticles {
  engine::FullOrderConfig config;
  mpm::ParticleInit particles;
  io::FrameData frame;
  Mat3<float> F0;

  TwoParticles() {
    config.dx = 0.1f;
    config.gravity = Vec3<float>(0.0f, -10.0f, 0.0f);
    config.transfer = mpm::Transfer::Apic;
    engine::MaterialSpec m;
    m.params = material::MaterialParams<float>::fixed_corotated(material::lame_from_young_poisson(1e5f, 0.3f));
    config.materials = {m};
    particles.mass = {2.0f, 3.0f};
    particles.volume0 = {0.002f, 0.003f};
    particles.material = {0, 0};
    F0 = Mat3<float>::identity();
    F0(0, 0) = 1.2f, F0(0, 1) = 0.1f, F0(2, 2) = 0.9f;
    // Planes of 2: x, v, F and C.
    frame.x = {1.0f, 0.0f, 0.0f, 2.0f, 0.0f, 0.5f};  // p0 at (1, 0, 0), p1 at (0, 2, 0.5)
    frame.v = {0.0f, 1.0f, 3.0f, 0.0f, 0.0f, 0.0f};  // p0 (0, 3, 0), p1 (1, 0, 0)
    frame.F.assign(18, 0.0f);
    frame.C.assign(18, 0.0f);
    for (int k = 0; k < 9; ++k) {
      frame.F[std::size_t(k) * 2] = F0(k / 3, k % 3);
      frame.F[std::size_t(k) * 2 + 1] = k % 4 == 0 ? 1.0f : 0.0f;
    }
    // p1 spins about z at 5 rad/s: C = [ω]×, C(0, 1) = −5, C(1, 0) = 5.
    frame.C[1 * 2 + 1] = -5.0f;
    frame.C[3 * 2 + 1] = 5.0f;
  }
};

TEST(FrameOutputs, DerivedFieldsFollowTheirDefinitions) {
  TwoParticles t;
  const FrameOutputs outputs(io::kStateFields | io::kDerivedFields, t.config, t.particles);
  outputs.add_to(t.frame);
  const material::MaterialParams<float>& params = t.config.materials[0].params;
  const Mat3<float> P = material::first_piola(params, t.F0);
  const double J = determinant(t.F0);
  EXPECT_NEAR(t.frame.J[0], J, 1e-6);
  EXPECT_FLOAT_EQ(t.frame.J[1], 1.0f);
  double mean = 0.0, sigma[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      sigma[i][j] = 0.0;
      for (int k = 0; k < 3; ++k) sigma[i][j] += double(P(i, k)) * t.F0(j, k) / J;
      EXPECT_NEAR(t.frame.stress[std::size_t(3 * i + j) * 2], sigma[i][j], 1e-6 * 1e5) << i << j;
      // At rest: no stress but the SVD's float rounding (~1e-6 μ).
      EXPECT_NEAR(t.frame.stress[std::size_t(3 * i + j) * 2 + 1], 0.0f, 1.0f);
    }
  for (int i = 0; i < 3; ++i) mean += sigma[i][i] / 3.0;
  // σ is symmetric for an isotropic law.
  EXPECT_NEAR(t.frame.stress[1 * 2], t.frame.stress[3 * 2], 1e-3);
  double s2 = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s2 += std::pow(sigma[i][j] - (i == j ? mean : 0.0), 2);
  EXPECT_NEAR(t.frame.von_mises[0], std::sqrt(1.5 * s2), 1e-6 * 1e5);
  EXPECT_GT(t.frame.von_mises[0], 0.0f);
  EXPECT_FLOAT_EQ(t.frame.energy_density[0], material::energy_density(params, t.F0));
  EXPECT_NEAR(t.frame.energy_density[1], 0.0f, 1e-3f);
}

TEST(FrameOutputs, TotalsSumEnergiesAndMomentaWithTheParticlesSpin) {
  TwoParticles t;
  const FrameOutputs outputs(io::kFieldX, t.config, t.particles);  // totals only
  outputs.add_to(t.frame);
  EXPECT_TRUE(t.frame.stress.empty());
  ASSERT_TRUE(t.frame.totals.has_value());
  const io::FrameTotals& totals = *t.frame.totals;
  EXPECT_DOUBLE_EQ(totals.kinetic_energy, 0.5 * 2.0 * 9.0 + 0.5 * 3.0 * 1.0);
  // −Σ m g·x with g = (0, −10, 0): p1 at height 2.
  EXPECT_DOUBLE_EQ(totals.gravitational_energy, 3.0 * 10.0 * 2.0);
  const double psi = material::energy_density(t.config.materials[0].params, t.F0);
  EXPECT_NEAR(totals.elastic_energy, 0.002 * psi, 1e-9 * std::fabs(psi));
  EXPECT_DOUBLE_EQ(totals.linear_momentum[0], 3.0);
  EXPECT_DOUBLE_EQ(totals.linear_momentum[1], 6.0);
  // x × m v: p0 (1, 0, 0) × 2 (0, 3, 0) = (0, 0, 6); p1 (0, 2, 0.5) × 3 (1, 0, 0) = (0, 1.5, −6); p1's
  // spin m Δx²/4 · 2ω = 3 · 0.0025 · (0, 0, 10) = (0, 0, 0.075).
  EXPECT_NEAR(totals.angular_momentum[0], 0.0, 1e-12);
  EXPECT_NEAR(totals.angular_momentum[1], 1.5, 1e-12);
  EXPECT_NEAR(totals.angular_momentum[2], 0.075, 1e-6);
}

TEST(FrameOutputs, ALearnedLawHasNoDerivedFieldsAndNoElasticEnergy) {
  TwoParticles t;
  t.config.materials[0].params = material::MaterialParams<float>::neural({1e4f, 1e4f});
  const std::string message = test::error_message([&] { FrameOutputs(io::kFieldStress, t.config, t.particles); });
  EXPECT_NE(message.find("output.fields: stress need"), std::string::npos) << message;
  const FrameOutputs totals_only(io::kStateFields, t.config, t.particles);
  totals_only.add_to(t.frame);
  EXPECT_TRUE(std::isnan(t.frame.totals->elastic_energy));
  EXPECT_DOUBLE_EQ(t.frame.totals->kinetic_energy, 10.5);
}

// A jelly cube spinning and drifting in free space (no gravity, far from the walls): APIC conserves
// linear and angular momentum, the latter with each particle's spin, and an elastic body its energy
// up to the transfers' small dissipation.
TEST(FrameOutputs, AFreeSpinningBodyConservesMomentaAndNearlyItsEnergy) {
  const scene::Scene scene = scene::parse_scene(R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05
[time]
end = 0.05
frame_rate = 100
dt = 5e-4
[materials.jelly]
preset = "jelly"
[[objects]]
velocity = [0.2, 0.0, -0.1]
angular_velocity = [1.0, 2.0, 3.0]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.3, 0.3, 0.3] }
[loads]
gravity = [0, 0, 0]
)",
                                                "spin.toml");
  const scene::SceneSetup setup = scene::build_scene(scene);
  const FrameOutputs outputs(io::kStateFields, setup.config, setup.particles);
  const std::unique_ptr<Simulation> sim = full_order_simulation(Exec::cpu(), setup.config, setup.particles);
  io::FrameData start = sim->capture();
  outputs.add_to(start);
  sim->advance_to(0.05, {});
  io::FrameData end = sim->capture();
  outputs.add_to(end);
  const io::FrameTotals &a = *start.totals, &b = *end.totals;
  double L = 0.0;
  for (int k = 0; k < 3; ++k) L += a.angular_momentum[std::size_t(k)] * a.angular_momentum[std::size_t(k)];
  L = std::sqrt(L);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.linear_momentum[std::size_t(k)], a.linear_momentum[std::size_t(k)], 1e-5 * 27.0 * 0.2);
    EXPECT_NEAR(b.angular_momentum[std::size_t(k)], a.angular_momentum[std::size_t(k)], 1e-4 * L) << k;
  }
  const double energy0 = a.kinetic_energy + a.elastic_energy, energy1 = b.kinetic_energy + b.elastic_energy;
  EXPECT_NEAR(energy1, energy0, 0.02 * energy0);
  EXPECT_EQ(a.gravitational_energy, 0.0);
}

// A jelly cube at dx = 0.1 for two frames, with `extra` (its output fields, a Dirichlet group) added.
std::string jelly_cube(const std::string& extra) {
  return R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.1
[time]
end = 0.02
frame_rate = 100
[materials.jelly]
preset = "jelly"
[[objects]]
shape = { type = "box", center = [0.5, 0.5, 0.5], size = [0.3, 0.3, 0.3] }
)" + extra;
}

TEST(FrameOutputs, ARunWritesTheSelectedFieldsAndTheTotalsOfEveryFrame) {
  test::ScratchFolder folder;
  const scene::Scene scene = scene::parse_scene(jelly_cube(R"(
[[dirichlet]]
region = { type = "box", center = [0.5, 0.4, 0.5], size = [0.4, 0.1, 0.4] }
[output]
fields = ["x", "J", "von_mises", "stress", "energy_density"]
)"),
                                                "fields.toml");
  RunOptions options;
  options.output = folder.file("fields.h5");
  options.progress = false;
  run_scene(Exec::cpu(), scene, options);
  const io::SnapshotReader reader(options.output);
  EXPECT_EQ(reader.fields(),
            io::kFieldX | io::kFieldJ | io::kFieldVonMises | io::kFieldStress | io::kFieldEnergyDensity);
  const std::size_t n = std::size_t(reader.particle_count());
  ASSERT_EQ(reader.header().group.size(), n);
  EXPECT_EQ(reader.header().group.front(), 0);  // the held bottom layer
  EXPECT_EQ(reader.header().group.back(), -1);  // the top is free
  for (std::int64_t k = 0; k < reader.frame_count(); ++k) {
    const io::FrameData frame = reader.read_frame(k);
    ASSERT_TRUE(frame.totals.has_value()) << "frame " << k;
    EXPECT_EQ(frame.J.size(), n);
    EXPECT_EQ(frame.stress.size(), 9 * n);
    EXPECT_TRUE(frame.v.empty());
  }
  // The body sags under gravity: it stores elastic energy and loses height.
  const io::FrameData last = reader.read_frame(reader.frame_count() - 1);
  EXPECT_GT(last.totals->elastic_energy, 0.0);
  EXPECT_LT(last.totals->gravitational_energy, reader.read_frame(0).totals->gravitational_energy);
  std::ifstream sidecar(folder.file("fields.xdmf"));
  std::stringstream text;
  text << sidecar.rdbuf();
  for (const char* name : {"\"J\"", "\"von_mises\"", "\"stress\"", "\"energy_density\"", "\"group\""})
    EXPECT_NE(text.str().find(std::string("Attribute Name=") + name), std::string::npos) << name;
}

TEST(FrameOutputs, UnknownFieldNamesAreRefusedListingTheKnownOnes) {
  const std::string message = test::error_message(
      [] { scene::parse_scene(jelly_cube("[output]\nfields = [\"x\", \"pressure\"]\n"), "bad.toml"); });
  EXPECT_NE(message.find("von_mises"), std::string::npos) << message;
}

}  // namespace
}  // namespace romp::run
