// Learned constitutive laws inside the full-order engine (scene materials `neural = "law.h5"`): each
// law acts on its own material's particles, the plastic law spares Dirichlet particles, a scene run
// follows the differentiable step with the same laws, and unusable laws are scene errors. Runs on
// the backend the binary was started with (CPU, or CUDA under the gpu label).
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/engine/full_order_sim.h"
#include "host/engine/neural_materials.h"
#include "host/nclaw/ground_truth.h"
#include "host/run/scene_runner.h"
#include "host/scene/material_library.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"
#include "host/scene/toml_reader.h"
#include "kernels/core/error.h"
#include "kernels/core/memory.h"
#include "nn/diffmpm/rollout.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/rest_stiffness.h"
#include "tests/support/late_write.h"
#include "tests/support/scratch_folder.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

// Seeded laws whose elastic part is scaled to the rest P-wave modulus `p_wave` (Pa; negative makes
// a law that gives way under compression) and whose plastic part is `plastic_gain` times the seeded
// one, so that both matter within a few substeps.
nn::nclaw::NeuralLaws scaled_laws(std::uint64_t seed, double p_wave, double plastic_gain = 100.0) {
  nn::nclaw::NeuralLaws laws = nn::nclaw::seeded_laws(seed, torch::kFloat32);
  const torch::NoGradGuard no_grad;
  const double found =
      nn::nclaw::rest_stiffness([&](const torch::Tensor& F) { return laws.elastic->forward(F); }, torch::kFloat32)
          .p_wave_modulus();
  laws.elastic->parameters().back().mul_(p_wave / found);  // the output layer: P is linear in it
  laws.plastic->parameters().back().mul_(plastic_gain);
  return laws;
}

std::string write_law(const test::ScratchFolder& folder, const std::string& name, const nn::nclaw::NeuralLaws& laws) {
  const std::string path = folder.file(name);
  nn::nclaw::write_law_file(path, laws, {"none (test)", 0, {}, 0.0});
  return path;
}

// [9, n] planes of F for n particles: I plus a fixed pseudo-random perturbation of size ~0.2.
std::vector<float> perturbed_deformations(Index n) {
  torch::manual_seed(5);
  const torch::Tensor F = torch::eye(3).reshape({9, 1}) + 0.2 * torch::randn({9, n});
  return std::vector<float>(F.data_ptr<float>(), F.data_ptr<float>() + 9 * n);
}

torch::Tensor column(const std::vector<float>& planes, Index n, Index p) {
  torch::Tensor c = torch::empty({9, 1});
  for (int k = 0; k < 9; ++k) c[k][0] = planes[std::size_t(k * n + p)];
  return c;
}

// torch::allclose's test (|actual − expected| ≤ atol + rtol |expected| everywhere), the same on every
// backend, with the largest excess and both tensors in the message when it fails.
::testing::AssertionResult all_close(const torch::Tensor& actual, const torch::Tensor& expected, double rtol,
                                     double atol) {
  const double excess = ((actual - expected).abs() - rtol * expected.abs()).max().item<double>();
  if (excess <= atol) return ::testing::AssertionSuccess();
  std::ostringstream message;
  message << "|actual - expected| - " << rtol << " |expected| reaches " << excess << ", above " << atol
          << "\n  actual   " << actual.flatten() << "\n  expected " << expected.flatten();
  return ::testing::AssertionFailure() << message.str();
}

// n particles at rest in one place, of unit mass and volume, with perturbed_deformations(n) as F and no
// Dirichlet group; the caller gives them their materials.
mpm::ParticleInit resting_particles(Index n) {
  mpm::ParticleInit init;
  init.x.assign(3 * n, 0.5f);
  init.v.assign(3 * n, 0.0f);
  init.F = perturbed_deformations(n);
  init.mass.assign(n, 1.0f);
  init.volume0.assign(n, 1.0f);
  init.dirichlet_group.assign(n, mpm::kNoDirichletGroup);
  return init;
}

TEST(NeuralMaterials, EachLawActsOnItsOwnMaterialsParticles) {
  const test::ScratchFolder folder;
  const Exec& exec = test::exec();
  nn::nclaw::NeuralLaws first = scaled_laws(1, 1e5), second = scaled_laws(2, 3e5);
  const std::vector<engine::MaterialSpec> materials = {
      {material::MaterialParams<float>::neural({1.0f, 1.0f}), 1000.0f, write_law(folder, "first.h5", first)},
      {material::MaterialParams<float>::fixed_corotated({1.0f, 1.0f}), 1000.0f, ""},
      {material::MaterialParams<float>::neural({1.0f, 1.0f}), 1000.0f, write_law(folder, "second.h5", second)}};
  constexpr Index n = 30;
  constexpr Index kHeld = 5;  // material 2, in a Dirichlet group: its plastic law must not touch it
  mpm::ParticleInit init = resting_particles(n);
  init.dirichlet_group[kHeld] = 0;
  for (Index p = 0; p < n; ++p) init.material.push_back(std::int32_t(p % 3));
  mpm::ParticleSet particles(exec.backend, init);
  engine::NeuralMaterials neural(exec, materials, n);
  ASSERT_FALSE(neural.empty());

  const Mat3Planes<const float> stress = neural.evaluate_stress(exec, particles.view());
  std::vector<float> P(9 * n);
  memory::copy(P.data(), Backend::Cpu, stress.data(), exec.backend, P.size() * sizeof(float), exec.stream);
  DeviceBuffer<std::int64_t> failure =
      DeviceBuffer<std::int64_t>::from_host(exec.backend, std::vector<std::int64_t>(mpm::kStageCount, mpm::kNoFailure));
  mpm::StepParams step;
  step.first_failure = failure.span();
  neural.project_plasticity(exec, particles.view(), step);
  const std::vector<float> F_after = particles.deformation_gradients_in_initial_order(exec);
  EXPECT_EQ(failure.to_host()[int(mpm::Stage::Plasticity)], mpm::kNoFailure);

  const torch::NoGradGuard no_grad;
  for (Index p = 0; p < n; ++p) {
    const torch::Tensor F = column(init.F, n, p);
    const int m = int(p % 3);
    const torch::Tensor expected_P = m == 1 ? torch::zeros({9, 1}) : (m == 0 ? first : second).elastic->forward(F);
    const torch::Tensor expected_F = m == 1 || p == kHeld ? F : (m == 0 ? first : second).plastic->forward(F);
    EXPECT_TRUE(all_close(column(P, n, p), expected_P, 1e-5, 1e-2)) << "stress of particle " << p;
    EXPECT_TRUE(all_close(column(F_after, n, p), expected_F, 1e-5, 1e-6)) << "F of particle " << p;
    if (m != 1 && p != kHeld) EXPECT_FALSE(torch::allclose(expected_F, F, 0.0, 1e-5)) << "the plastic law did nothing";
  }
}

// The laws run on the engine's stream: the stress of an F that a kernel queued just before wrote (late)
// is the stress of the new F, with no synchronisation between them. The stream is one of its own,
// not ordered with the legacy default stream, as LibTorch's streams and a captured substep's are not.
TEST(NeuralMaterials, StressFollowsTheKernelsQueuedBeforeItOnTheEnginesStream) {
  const test::ScratchFolder folder;
  const test::StreamOfItsOwn stream(test::exec());
  const Exec& exec = stream.exec();
  nn::nclaw::NeuralLaws laws = scaled_laws(3, 1e5);
  const std::vector<engine::MaterialSpec> materials = {
      {material::MaterialParams<float>::neural({1.0f, 1.0f}), 1000.0f, write_law(folder, "law.h5", laws)}};
  constexpr Index n = 4096;
  mpm::ParticleInit init = resting_particles(n);
  init.material.assign(n, 0);
  mpm::ParticleSet particles(exec.backend, init);
  engine::NeuralMaterials neural(exec, materials, n);

  constexpr float kFactor = 1.25f;
  test::scale_late(exec, Span<float>(particles.view().F.data(), 9 * n), kFactor, 200000);
  const Mat3Planes<const float> stress = neural.evaluate_stress(exec, particles.view());
  std::vector<float> P(9 * n);
  memory::copy(P.data(), Backend::Cpu, stress.data(), exec.backend, P.size() * sizeof(float), exec.stream);

  const torch::NoGradGuard no_grad;
  const torch::Tensor F = torch::tensor(init.F).reshape({9, n}) * kFactor;
  const torch::Tensor expected = laws.elastic->forward(F);
  const torch::Tensor actual = torch::tensor(P).reshape({9, n});
  EXPECT_TRUE(all_close(actual, expected, 1e-5, 1e-2));
  // Had the laws read F before the late write, they would have found the stress of the old F.
  const torch::Tensor stale = laws.elastic->forward(torch::tensor(init.F).reshape({9, n}));
  EXPECT_GT((stale - expected).abs().max().item<double>(), 100.0 * (actual - expected).abs().max().item<double>());
}

// The NCLaw training cube dropped onto the floor's wall, with `material` as its material table.
std::string dropped_cube_scene(const std::string& material) {
  return R"(
[domain]
size = [1.0, 1.0, 1.0]
dx = 0.05
[time]
end = 0.02
frame_rate = 2000
dt = 5e-4
[boundary]
wall_cells = 3
contact = "separate"
[materials.body]
)" + material +
         R"(
[[objects]]
velocity = [0.5, -1.5, 0.0]
angular_velocity = [0.0, 0.0, 4.0]
shape = { type = "box", center = [0.5, 0.26, 0.5], size = [0.2, 0.2, 0.2] }
sampling = { per_cell = 2 }
[loads]
gravity = [0.0, -9.8, 0.0]
)";
}

// A learned law in a scene behaves as it did in training: `romp run` of a scene whose material is a
// law file follows the differentiable step (the trainer's simulator) with the same two networks,
// through the impact that compresses the cube and sets both laws to work.
TEST(NeuralMaterials, SceneRunFollowsTheDifferentiableStepWithTheSameLaws) {
  const test::ScratchFolder folder;
  nn::nclaw::NeuralLaws laws = scaled_laws(4, 1e4, 10.0);
  write_law(folder, "law.h5", laws);
  run::RunOptions options;
  options.output = folder.file("cube.h5");
  options.progress = false;
  const scene::Scene scene = scene::parse_scene(dropped_cube_scene("neural = \"law.h5\""), folder.file("cube.toml"));
  run::run_scene(test::exec(), scene, options);

  const nclaw::GroundTruth engine = nclaw::read_ground_truth(options.output);
  const nn::nclaw::Trajectory& t = engine.trajectory;
  const nn::diffmpm::DiffMpm sim(engine.config, t.mass, t.volume);
  const torch::NoGradGuard no_grad;
  const int64_t steps = t.frame_count() - 1;
  const nn::diffmpm::Rollout replay = nn::diffmpm::rollout(sim, t.state(0), laws.constitutive(), {steps, 0});
  const nn::diffmpm::ConstitutiveLaws stress_free{[](const torch::Tensor& F) { return torch::zeros_like(F); }, {}, {}};
  const nn::diffmpm::Rollout ballistic = nn::diffmpm::rollout(sim, t.state(0), stress_free, {steps, 0});
  const torch::Tensor engine_x = t.x.slice(0, 1);
  const double error = (replay.positions - engine_x).abs().max().item<double>();
  const double law_effect = (ballistic.positions - engine_x).abs().max().item<double>();
  std::printf("max |x_diffmpm - x_engine| over %lld substeps: %.3g m (the laws move particles by %.3g m)\n",
              (long long)steps, error, law_effect);
  // CUDA sums particle contributions in another order than the CPU: rounding, not a different step.
  const double tolerance = test::exec().is_cuda() ? 1e-4 : 1e-5;
  EXPECT_LE(error, tolerance);
  EXPECT_GE(law_effect, 20.0 * tolerance);
}

TEST(NeuralMaterials, SceneMaterialCarriesTheLawAndItsRestStiffness) {
  const test::ScratchFolder folder;
  write_law(folder, "law.h5", scaled_laws(4, 2e5));
  const scene::Scene scene =
      scene::parse_scene(dropped_cube_scene("neural = \"law.h5\"\ndensity = 500.0"), folder.file("cube.toml"));
  const engine::MaterialSpec material = scene::to_material_spec(scene.materials.at(0));
  EXPECT_EQ(material.params.model, material::MaterialModel::Neural);
  EXPECT_EQ(material.neural_law, folder.file("law.h5"));
  EXPECT_EQ(material.density, 500.0f);
  // scaled_laws measured the modulus in float; the scene measures it in double.
  EXPECT_NEAR(material.params.lambda + 2.0f * material.params.mu, 2e5f, 2e3f);
  // The resolved scene (what snapshots store and sweep members are written from) names the law by its
  // absolute path, so it reads the same from another folder.
  const scene::Scene elsewhere = scene::parse_scene(scene.resolved_text, "/nonexistent/elsewhere.toml");
  EXPECT_EQ(elsewhere.materials.at(0).neural_law, folder.file("law.h5"));
}

// `romp run --law body=law.h5`: the analytic material of a scene replaced by a learned law, its
// density kept, and the resolved scene (stored in every snapshot) saying so.
TEST(NeuralMaterials, ALearnedLawReplacesAnAnalyticMaterialByName) {
  const test::ScratchFolder folder;
  const std::string law = write_law(folder, "law.h5", scaled_laws(4, 2e5));
  const std::string text = dropped_cube_scene("preset = \"jelly\"\ndensity = 800.0");
  const scene::Scene scene = scene::parse_scene(text, folder.file("cube.toml"), {}, {{"body", law}});
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].model, material::MaterialModel::Neural);
  EXPECT_EQ(scene.materials[0].neural_law, law);
  EXPECT_EQ(scene.materials[0].density, 800.0);
  EXPECT_NE(scene.resolved_text.find("neural = \"" + law + "\""), std::string::npos) << scene.resolved_text;
  try {
    scene::parse_scene(text, folder.file("cube.toml"), {}, {{"jelly", law}});
    FAIL() << "accepted";
  } catch (const scene::SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("material 'jelly', which the scene lacks (it has: body)"),
              std::string::npos)
        << error.what();
  }
}

// Parsing and sampling a scene (`romp check`) run no network: a law that gives way under compression
// passes both, and is refused where the run is set up, with the error located where the scene names it.
TEST(NeuralMaterials, ALawThatGivesWayUnderCompressionIsASceneErrorAtSetUp) {
  const test::ScratchFolder folder;
  write_law(folder, "soft.h5", scaled_laws(4, -1e5));
  const scene::Scene scene = scene::parse_scene(dropped_cube_scene("neural = \"soft.h5\""), folder.file("cube.toml"));
  EXPECT_NO_THROW(scene::sample_scene(scene));  // what `romp check` sets up
  try {
    scene::build_scene(scene);
    FAIL() << "accepted";
  } catch (const scene::SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(folder.file("cube.toml") + ":"), std::string::npos) << message;
    EXPECT_NE(message.find("materials.body.neural"), std::string::npos) << message;
    EXPECT_NE(message.find("soft.h5"), std::string::npos) << message;
    EXPECT_NE(message.find("P-wave modulus"), std::string::npos) << message;
  }
}

// What the parser does check without LibTorch: that the file is a law file.
TEST(NeuralMaterials, AFileThatIsNotALawIsASceneErrorWhenParsed) {
  const test::ScratchFolder folder;
  std::ofstream(folder.file("other.h5")) << "not HDF5";
  try {
    scene::parse_scene(dropped_cube_scene("neural = \"other.h5\""), folder.file("cube.toml"));
    FAIL() << "accepted";
  } catch (const scene::SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("materials.body.neural"), std::string::npos) << message;
    EXPECT_NE(message.find("other.h5"), std::string::npos) << message;
  }
}

TEST(NeuralMaterials, TheImplicitIntegratorRefusesThem) {
  const test::ScratchFolder folder;
  engine::FullOrderConfig config;
  config.dx = 0.05f;
  config.domain_cells = {20, 20, 20};
  config.integrator = engine::Integrator::Implicit;
  config.materials = {{material::MaterialParams<float>::neural({1e4f, 1e4f}), 1000.0f,
                       write_law(folder, "law.h5", scaled_laws(4, 1e5))}};
  mpm::ParticleInit init;
  init.x.assign(3, 0.5f);
  init.v.assign(3, 0.0f);
  init.mass = {1.0f};
  init.volume0 = {1e-6f};
  init.material = {0};
  init.dirichlet_group = {mpm::kNoDirichletGroup};
  try {
    engine::FullOrderSim sim(test::exec(), config, init);
    FAIL() << "accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("neural laws run with the explicit integrator"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace romp
