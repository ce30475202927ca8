// The ROM model file's content: writing the layout of rom_model_file_content.h and reading it back with every
// rule checked, without LibTorch.
#include "nn/rom/rom_model_file_content.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/rom/deformation_map_eval.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/encoder_shape.h"

namespace romp::nn::rom {
namespace {

constexpr const char* kMapInput = "[xhat, Xbar]";
constexpr const char* kMapOutput = "standardised displacement";
constexpr const char* kActivation = "elu";
constexpr const char* kEncoderKind = "conv1d";

// The sizes a model may declare. Layers are sized from them before any weight is read, so a damaged or hostile
// file must not ask for more than a model could be: these are far above the paper's (a width of 30 to 128,
// 5 hidden layers, r ≤ 7, a few thousand encoder points) and the fused kernels' latent limit.
constexpr std::int64_t kMaxWidth = 4096, kMaxHiddenLayers = 64, kMaxEncoderPoints = std::int64_t(1) << 24,
                       kMaxParticles = (std::int64_t(1) << 31) - 1;
// A sweep has at most 1,000,000 members and as many values in all (host/scene/sweep.cpp).
constexpr std::int64_t kMaxMemberValues = 1000000;
// What the training record's counts may be (they size nothing).
constexpr std::int64_t kUnbounded = std::numeric_limits<std::int64_t>::max();

std::string object_path(const io::hdf5::Group& group, const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  return group.path() == "/" ? "/" + path : group.path() + "/" + path;
}

[[noreturn]] void invalid(const io::hdf5::Group& group, const std::string& what, const std::string& problem) {
  throw io::UnusableFileError(group.label() + ": " + what + " " + object_path(group, "") + ": " + problem);
}

std::int64_t read_in(const io::hdf5::Group& group, const std::string& name, std::int64_t minimum,
                     std::int64_t maximum) {
  const std::int64_t value = group.read_int64_attribute(name);
  if (value < minimum || value > maximum) {
    throw io::UnusableFileError(group.label() + ": attribute " + object_path(group, name) + ": " +
                                std::to_string(value) + " is outside [" + std::to_string(minimum) + ", " +
                                std::to_string(maximum) + "]");
  }
  return value;
}

void expect_int(const io::hdf5::Group& group, const std::string& name, std::int64_t expected) {
  const std::int64_t value = group.read_int64_attribute(name);
  if (value != expected) {
    throw io::UnusableFileError(group.label() + ": attribute " + object_path(group, name) + ": " +
                                std::to_string(value) + ", expected " + std::to_string(expected));
  }
}

void expect_string(const io::hdf5::Group& group, const std::string& name, const std::string& expected) {
  const std::string value = group.read_string_attribute(name);
  if (value != expected) {
    throw io::UnusableFileError(group.label() + ": attribute " + object_path(group, name) + ": \"" + value +
                                "\", expected \"" + expected + "\"");
  }
}

io::hdf5::Shape shape_of(const std::vector<std::int64_t>& extents) {
  return io::hdf5::Shape(extents.begin(), extents.end());
}

void write_layer(io::hdf5::Group& group, const std::string& name, const StoredLayer& layer) {
  group.write_dataset(name + "/weight", shape_of(layer.weight_shape), layer.weight);
  group.write_dataset(name + "/bias", {std::uint64_t(layer.weight_shape.at(0))}, layer.bias);
}

StoredLayer read_layer(const io::hdf5::Group& group, const std::string& name,
                       const std::vector<std::int64_t>& weight_shape) {
  return {weight_shape, read_finite_floats(group, name + "/weight", weight_shape),
          read_finite_floats(group, name + "/bias", {weight_shape[0]})};
}

void write_values(io::hdf5::Group& group, const std::string& name, const std::array<float, 3>& values) {
  group.write_dataset(name, {3}, values.data());
}

std::array<float, 3> read_values(const io::hdf5::Group& group, const std::string& name) {
  const std::vector<float> values = group.read_dataset<float>(name, {3});
  return {values[0], values[1], values[2]};
}

void write_map(io::hdf5::Group& root, const RomModelFileContent& content) {
  io::hdf5::Group normalisation = root.create_group("normalisation");
  write_values(normalisation, "X_min", content.normalisation.X_min);
  write_values(normalisation, "X_max", content.normalisation.X_max);
  write_values(normalisation, "u_mean", content.normalisation.u_mean);
  write_values(normalisation, "u_std", content.normalisation.u_std);

  io::hdf5::Group group = root.create_group("map");
  group.write_attribute("kind", content.architecture.hidden_layers == 0 ? "linear" : "mlp");
  group.write_attribute("activation", kActivation);
  group.write_attribute("hidden_layers", content.architecture.hidden_layers);
  group.write_attribute("width", content.architecture.width);
  group.write_attribute("input", kMapInput);
  group.write_attribute("output", kMapOutput);
  for (std::size_t k = 0; k < content.map_layers.size(); ++k)
    write_layer(group, "layer_" + std::to_string(k), content.map_layers[k]);
}

void read_map(const io::hdf5::Group& root, RomModelFileContent& content) {
  const io::hdf5::Group normalisation_group = root.open_group("normalisation");
  MapNormalisationValues& n = content.normalisation;
  n.X_min = read_values(normalisation_group, "X_min");
  n.X_max = read_values(normalisation_group, "X_max");
  n.u_mean = read_values(normalisation_group, "u_mean");
  n.u_std = read_values(normalisation_group, "u_std");
  const std::string problem = normalisation_problem(n);
  if (!problem.empty()) invalid(normalisation_group, "group", problem);

  const io::hdf5::Group group = root.open_group("map");
  const std::string kind = group.read_string_attribute("kind");
  if (kind != "mlp" && kind != "linear") invalid(group, "group", "kind \"" + kind + "\" is not mlp or linear");
  expect_string(group, "activation", kActivation);
  expect_string(group, "input", kMapInput);
  expect_string(group, "output", kMapOutput);
  MapArchitecture& architecture = content.architecture;
  architecture.hidden_layers = read_in(group, "hidden_layers", 0, kMaxHiddenLayers);
  architecture.width = read_in(group, "width", 1, kMaxWidth);
  if ((kind == "linear") != (architecture.hidden_layers == 0))
    invalid(group, "group",
            "kind \"" + kind + "\" with " + std::to_string(architecture.hidden_layers) + " hidden layers");
  for (const auto& [out, in] : map_layer_shapes(architecture)) {
    const std::string name = "layer_" + std::to_string(content.map_layers.size());
    content.map_layers.push_back(read_layer(group, name, {out, in}));
  }
}

void write_encoder(io::hdf5::Group& root, const RomModelFileContent& content) {
  io::hdf5::Group group = root.create_group("encoder");
  group.write_attribute("kind", kEncoderKind);
  group.write_attribute("activation", kActivation);
  group.write_attribute("points", std::int64_t(content.encoder_indices.size()));
  group.write_attribute("particle_count", content.training.particle_count);
  group.write_attribute("conv_layers", std::int64_t(content.encoder_convolutions.size()));
  group.write_attribute("kernel", kEncoderKernel);
  group.write_attribute("stride", kEncoderStride);
  group.write_attribute("channels", kEncoderChannels);
  group.write_attribute("hidden", kEncoderHidden);
  group.write_dataset("indices", {std::uint64_t(content.encoder_indices.size())}, content.encoder_indices);
  for (std::size_t k = 0; k < content.encoder_convolutions.size(); ++k)
    write_layer(group, "conv_" + std::to_string(k), content.encoder_convolutions[k]);
  for (std::size_t k = 0; k < content.encoder_linears.size(); ++k)
    write_layer(group, "linear_" + std::to_string(k), content.encoder_linears[k]);
}

void read_encoder(const io::hdf5::Group& root, RomModelFileContent& content) {
  const io::hdf5::Group group = root.open_group("encoder");
  expect_string(group, "kind", kEncoderKind);
  expect_string(group, "activation", kActivation);
  expect_int(group, "kernel", kEncoderKernel);
  expect_int(group, "stride", kEncoderStride);
  expect_int(group, "channels", kEncoderChannels);
  expect_int(group, "hidden", kEncoderHidden);
  const std::int64_t points = read_in(group, "points", 1, kMaxEncoderPoints);
  const std::int64_t particles = read_in(group, "particle_count", points, kMaxParticles);
  expect_int(group, "conv_layers", encoder_conv_layers(points));
  content.training.particle_count = particles;
  content.encoder_indices = group.read_dataset<std::int64_t>("indices", {std::uint64_t(points)});
  const std::vector<std::int64_t>& indices = content.encoder_indices;
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] < 0 || indices[i] >= particles || (i > 0 && indices[i] <= indices[i - 1])) {
      invalid(group, "group",
              "indices must increase within 0 .. particle_count − 1 = " + std::to_string(particles - 1));
    }
  }
  for (std::int64_t k = 0; k < encoder_conv_layers(points); ++k) {
    content.encoder_convolutions.push_back(
        read_layer(group, "conv_" + std::to_string(k), {kEncoderChannels, kEncoderChannels, kEncoderKernel}));
  }
  content.encoder_linears[0] = read_layer(group, "linear_0", {kEncoderHidden, encoder_conv_features(points)});
  content.encoder_linears[1] = read_layer(group, "linear_1", {content.architecture.latent, kEncoderHidden});
}

void write_errors(io::hdf5::Group& group, const std::string& split, const ReconstructionErrors& errors) {
  group.write_attribute(split + "_position_error", errors.position);
  group.write_attribute(split + "_F_error", errors.F);
  group.write_attribute(split + "_velocity_error", errors.velocity);
}

ReconstructionErrors read_errors(const io::hdf5::Group& group, const std::string& split) {
  return {group.read_double_attribute(split + "_position_error"), group.read_double_attribute(split + "_F_error"),
          group.read_double_attribute(split + "_velocity_error")};
}

void write_training(io::hdf5::Group& root, const TrainingRecord& record) {
  const TrainingSettings& s = record.settings;
  io::hdf5::Group group = root.create_group("training");
  group.write_attribute("sweep_dir", record.sweep_dir);
  group.write_attribute("parameter_names", record.parameter_names);
  group.write_attribute("epochs", s.epochs);
  group.write_attribute("epochs_done", record.epochs_done);
  group.write_attribute("batch", s.batch);
  group.write_attribute("points", s.points);
  group.write_attribute("encoder_points", s.encoder_points);
  group.write_attribute("seed", std::int64_t(s.seed));
  group.write_attribute("lambda_F", s.loss_weights.F);
  group.write_attribute("lambda_v", s.loss_weights.velocity);
  group.write_attribute("learning_rate", s.learning_rate);
  group.write_attribute("decay_at", s.decay_at);
  group.write_attribute("derivatives", to_string(s.derivatives));
  write_errors(group, "train", record.train_errors);
  write_errors(group, "test", record.test_errors);

  io::hdf5::Group members = group.create_group("members");
  const std::uint64_t m = record.members.size(), p = record.parameter_names.size();
  std::vector<std::int64_t> index;
  std::vector<std::int32_t> test;
  std::vector<double> values;
  std::vector<std::string> snapshots;
  for (const SweepMember& member : record.members) {
    index.push_back(member.index);
    test.push_back(member.test ? 1 : 0);
    values.insert(values.end(), member.values.begin(), member.values.end());
    snapshots.push_back(member.snapshot);
  }
  members.write_dataset("index", {m}, index);
  members.write_dataset("test", {m}, test);
  members.write_dataset("values", {m, p}, values);
  members.write_attribute("snapshots", snapshots);
}

void read_training(const io::hdf5::Group& root, TrainingRecord& record) {
  const io::hdf5::Group group = root.open_group("training");
  record.sweep_dir = group.read_string_attribute("sweep_dir");
  record.parameter_names = group.read_strings_attribute("parameter_names");
  TrainingSettings& s = record.settings;
  s.epochs = read_in(group, "epochs", 1, kUnbounded);
  record.epochs_done = read_in(group, "epochs_done", 0, kUnbounded);
  s.batch = read_in(group, "batch", 1, kUnbounded);
  s.points = read_in(group, "points", 1, kUnbounded);
  s.encoder_points = read_in(group, "encoder_points", 0, kUnbounded);
  s.seed = std::uint64_t(group.read_int64_attribute("seed"));
  s.loss_weights.F = group.read_double_attribute("lambda_F");
  s.loss_weights.velocity = group.read_double_attribute("lambda_v");
  s.learning_rate = group.read_double_attribute("learning_rate");
  s.decay_at = group.read_doubles_attribute("decay_at");
  const std::string derivatives = group.read_string_attribute("derivatives");
  if (derivatives != "analytic" && derivatives != "autograd")
    invalid(group, "group", "derivatives \"" + derivatives + "\" is not analytic or autograd");
  s.derivatives = derivatives == "analytic" ? DerivativeMethod::Analytic : DerivativeMethod::Autograd;
  record.train_errors = read_errors(group, "train");
  record.test_errors = read_errors(group, "test");

  const io::hdf5::Group members = group.open_group("members");
  const io::hdf5::Shape index_shape = members.dataset_shape("index");
  if (index_shape.size() != 1) invalid(members, "group", "index must be one-dimensional");
  const std::uint64_t m = index_shape[0], p = record.parameter_names.size();
  if (m > std::uint64_t(kMaxMemberValues) || m * std::max<std::uint64_t>(p, 1) > std::uint64_t(kMaxMemberValues)) {
    invalid(members, "group",
            std::to_string(m) + " members of " + std::to_string(p) + " parameters: a sweep holds at most " +
                std::to_string(kMaxMemberValues) + " values");
  }
  const std::vector<std::int64_t> index = members.read_dataset<std::int64_t>("index", {m});
  const std::vector<std::int32_t> test = members.read_dataset<std::int32_t>("test", {m});
  const std::vector<double> values = members.read_dataset<double>("values", {m, p});
  const std::vector<std::string> snapshots = members.read_strings_attribute("snapshots");
  if (snapshots.size() != m) invalid(members, "group", "attribute snapshots must name " + std::to_string(m) + " files");
  for (std::uint64_t i = 0; i < m; ++i) {
    record.members.push_back({index[i], std::vector<double>(values.begin() + i * p, values.begin() + (i + 1) * p),
                              test[i] != 0, snapshots[i]});
  }
}

}  // namespace

std::vector<float> read_finite_floats(const io::hdf5::Group& group, const std::string& path,
                                      const std::vector<std::int64_t>& shape) {
  std::vector<float> values = group.read_dataset<float>(path, shape_of(shape));
  for (float value : values) {
    if (!std::isfinite(value))
      throw io::UnusableFileError(group.label() + ": dataset " + object_path(group, path) + ": not finite");
  }
  return values;
}

void write_model_content(io::hdf5::Group& root, const RomModelFileContent& content) {
  root.write_attribute("romp_version", content.training.romp_version);
  root.write_attribute("commit", content.training.commit);
  root.write_attribute("latent", content.architecture.latent);
  write_map(root, content);
  write_encoder(root, content);
  write_training(root, content.training);
}

RomModelFileContent read_model_content(const io::hdf5::Group& root) {
  RomModelFileContent content;
  content.architecture.latent = read_in(root, "latent", 1, romp::rom::kMaxMapLatent);
  read_map(root, content);
  read_encoder(root, content);
  read_training(root, content.training);
  content.training.settings.architecture = content.architecture;
  content.training.romp_version = root.read_string_attribute("romp_version");
  content.training.commit = root.read_string_attribute("commit");
  return content;
}

RomModelFileContent read_rom_model_file_content(const std::string& path) {
  return read_model_content(io::open_versioned_file(path, kRomModelFileFormat));
}

}  // namespace romp::nn::rom
