// load_reduced_model: a model file becomes the fused evaluator's weights and the encoder's x̂ of the
// scene's initial state; a scene that samples other points than the training snapshots is refused.
#include "host/engine/rom_model_loader.h"

#include <gtest/gtest.h>

#include "nn/rom/fused_map.h"
#include "nn/rom/rom_model_file.h"
#include "tests/support/scratch_folder.h"

namespace romp {
namespace {

constexpr std::int64_t kPoints = 40;

// A freshly initialised model for 40 points in the unit box (as the trainer starts one), written to `path`.
nn::rom::RomModel write_model(const std::string& path) {
  torch::manual_seed(5);
  nn::rom::RomDataset data;
  data.dir = "/sweeps/small";
  data.parameter_names = {"gravity"};
  data.members = {{0, {9.8}, false, "member_000000.h5"}};
  data.X = torch::rand({kPoints, 3});
  data.encoder_indices = torch::arange(0, kPoints, 2, torch::kInt64);
  data.train.x = data.X + 0.05 * torch::randn({3, kPoints, 3});
  nn::rom::TrainingSettings settings;
  settings.architecture = {3, 2, 16};
  settings.encoder_points = kPoints / 2;
  nn::rom::RomModel model = nn::rom::initial_model(data, settings);
  nn::rom::write_rom_model(path, model);
  return model;
}

mpm::ParticleInit points(std::int64_t n) {
  mpm::ParticleInit init;
  for (std::int64_t i = 0; i < 3 * n; ++i) init.x.push_back(0.01f * float(i % 97));
  init.v.assign(std::size_t(3 * n), 0.0f);
  init.mass.assign(std::size_t(n), 1.0f);
  init.volume0.assign(std::size_t(n), 1.0f);
  init.material.assign(std::size_t(n), 0);
  init.dirichlet_group.assign(std::size_t(n), -1);
  return init;
}

TEST(RomModelLoader, EncodesTheInitialStateAndPacksTheMap) {
  const test::ScratchFolder folder;
  const std::string path = folder.file("model.h5");
  const nn::rom::RomModel model = write_model(path);
  const mpm::ParticleInit init = points(kPoints);
  const engine::LoadedReducedModel loaded = engine::load_reduced_model(path, init);

  const torch::Tensor x = torch::from_blob(const_cast<float*>(init.x.data()), {3, kPoints}).t().unsqueeze(0);
  const torch::Tensor expected = model.encode(x.contiguous()).squeeze(0).detach();
  ASSERT_EQ(std::int64_t(loaded.xhat.size()), 3);
  for (int j = 0; j < 3; ++j) EXPECT_FLOAT_EQ(loaded.xhat[j], expected[j].item<float>());
  EXPECT_EQ(loaded.map.parameters, nn::rom::fused_weights(*model.map).parameters);
  EXPECT_NE(loaded.description.find(path), std::string::npos);
}

TEST(RomModelLoader, AnotherSamplingIsRefusedNamingTheFileAndBothCounts) {
  const test::ScratchFolder folder;
  const std::string path = folder.file("model.h5");
  write_model(path);
  const std::string message = test::error_message([&] { engine::load_reduced_model(path, points(kPoints + 1)); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("40 material points"), std::string::npos) << message;
  EXPECT_NE(message.find("samples 41"), std::string::npos) << message;
}

}  // namespace
}  // namespace romp
