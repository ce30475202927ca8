// The ROM model file: writing the layout of rom_model_file.h and reading it back with every rule checked.
#include "nn/rom/rom_model_file.h"

#include <cmath>
#include <limits>

#include "kernels/core/error.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::nn::rom {
namespace {

constexpr const char* kMapInput = "[xhat, Xbar]";
constexpr const char* kMapOutput = "standardised displacement";
constexpr const char* kActivation = "elu";
constexpr const char* kEncoderKind = "conv1d";

std::string object_path(const io::hdf5::Group& group, const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  return group.path() == "/" ? "/" + path : group.path() + "/" + path;
}

[[noreturn]] void invalid(const io::hdf5::Group& group, const std::string& what, const std::string& problem) {
  throw io::UnusableFileError(group.label() + ": " + what + " " + object_path(group, "") + ": " + problem);
}

// The sizes a model may declare. Modules are built from them before any weight is read, so a damaged or
// hostile file must not ask for more than a model could be: these are far above the paper's (a width of
// 30 to 128, 5 hidden layers, r ≤ 7, a few thousand encoder points) and the fused kernels' latent limit.
constexpr std::int64_t kMaxWidth = 4096, kMaxHiddenLayers = 64, kMaxEncoderPoints = std::int64_t(1) << 24,
                       kMaxParticles = (std::int64_t(1) << 31) - 1;
// What the training record's counts may be (they size nothing).
constexpr std::int64_t kUnbounded = std::numeric_limits<std::int64_t>::max();

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

void write_affine(io::hdf5::Group& group, const std::string& name, const torch::Tensor& weight,
                  const torch::Tensor& bias) {
  write_tensor(group, name + "/weight", weight);
  write_tensor(group, name + "/bias", bias);
}

// Copies a stored weight or bias of the shape `target` has into it.
void load(const io::hdf5::Group& group, const std::string& path, const torch::Tensor& target) {
  const torch::Tensor stored = read_tensor(group, path, target.sizes().vec());
  torch::NoGradGuard no_grad;
  target.copy_(stored);
}

void write_map(io::hdf5::Group& root, const DeformationMapImpl& map) {
  const MapNormalisation n = map.normalisation();
  io::hdf5::Group normalisation = root.create_group("normalisation");
  write_tensor(normalisation, "X_min", n.X_min);
  write_tensor(normalisation, "X_max", n.X_max);
  write_tensor(normalisation, "u_mean", n.u_mean);
  write_tensor(normalisation, "u_std", n.u_std);

  io::hdf5::Group group = root.create_group("map");
  group.write_attribute("kind", map.is_linear() ? "linear" : "mlp");
  group.write_attribute("activation", kActivation);
  group.write_attribute("hidden_layers", map.architecture().hidden_layers);
  group.write_attribute("width", map.architecture().width);
  group.write_attribute("input", kMapInput);
  group.write_attribute("output", kMapOutput);
  for (std::size_t k = 0; k < map.layers().size(); ++k)
    write_affine(group, "layer_" + std::to_string(k), map.layers()[k]->weight, map.layers()[k]->bias);
}

DeformationMap read_map(const io::hdf5::Group& root, std::int64_t latent) {
  const io::hdf5::Group normalisation_group = root.open_group("normalisation");
  MapNormalisation n;
  n.X_min = read_tensor(normalisation_group, "X_min", {3});
  n.X_max = read_tensor(normalisation_group, "X_max", {3});
  n.u_mean = read_tensor(normalisation_group, "u_mean", {3});
  n.u_std = read_tensor(normalisation_group, "u_std", {3});
  const std::string problem = normalisation_problem(n);
  if (!problem.empty()) invalid(normalisation_group, "group", problem);

  const io::hdf5::Group group = root.open_group("map");
  const std::string kind = group.read_string_attribute("kind");
  if (kind != "mlp" && kind != "linear") invalid(group, "group", "kind \"" + kind + "\" is not mlp or linear");
  expect_string(group, "activation", kActivation);
  expect_string(group, "input", kMapInput);
  expect_string(group, "output", kMapOutput);
  MapArchitecture architecture;
  architecture.latent = latent;
  architecture.hidden_layers = read_in(group, "hidden_layers", 0, kMaxHiddenLayers);
  architecture.width = read_in(group, "width", 1, kMaxWidth);
  if ((kind == "linear") != (architecture.hidden_layers == 0))
    invalid(group, "group",
            "kind \"" + kind + "\" with " + std::to_string(architecture.hidden_layers) + " hidden layers");
  DeformationMap map(architecture, n);
  for (std::size_t k = 0; k < map->layers().size(); ++k) {
    const std::string name = "layer_" + std::to_string(k);
    load(group, name + "/weight", map->layers()[k]->weight);
    load(group, name + "/bias", map->layers()[k]->bias);
  }
  return map;
}

void write_encoder(io::hdf5::Group& root, const RomModel& model) {
  const EncoderImpl& encoder = *model.encoder;
  io::hdf5::Group group = root.create_group("encoder");
  group.write_attribute("kind", kEncoderKind);
  group.write_attribute("activation", kActivation);
  group.write_attribute("points", encoder.points());
  group.write_attribute("particle_count", model.training.particle_count);
  group.write_attribute("conv_layers", std::int64_t(encoder.convolutions().size()));
  group.write_attribute("kernel", kEncoderKernel);
  group.write_attribute("stride", kEncoderStride);
  group.write_attribute("channels", kEncoderChannels);
  group.write_attribute("hidden", kEncoderHidden);
  const torch::Tensor indices = model.encoder_indices.to(torch::kCPU, torch::kInt64).contiguous();
  group.write_dataset("indices", {std::uint64_t(indices.numel())}, indices.data_ptr<std::int64_t>());
  for (std::size_t k = 0; k < encoder.convolutions().size(); ++k)
    write_affine(group, "conv_" + std::to_string(k), encoder.convolutions()[k]->weight,
                 encoder.convolutions()[k]->bias);
  for (std::size_t k = 0; k < encoder.linears().size(); ++k)
    write_affine(group, "linear_" + std::to_string(k), encoder.linears()[k]->weight, encoder.linears()[k]->bias);
}

// The encoder and its indices; returns the training snapshots' particle count.
std::int64_t read_encoder(const io::hdf5::Group& root, RomModel& model) {
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
  const std::vector<std::int64_t> indices = group.read_dataset<std::int64_t>("indices", {std::uint64_t(points)});
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] < 0 || indices[i] >= particles || (i > 0 && indices[i] <= indices[i - 1])) {
      invalid(group, "group",
              "indices must increase within 0 .. particle_count − 1 = " + std::to_string(particles - 1));
    }
  }
  model.encoder_indices = torch::tensor(indices, torch::kInt64);
  const MapNormalisation n = model.map->normalisation();
  model.encoder = Encoder(points, model.map->architecture().latent, n.X_min, n.X_max);
  for (std::size_t k = 0; k < model.encoder->convolutions().size(); ++k) {
    const std::string name = "conv_" + std::to_string(k);
    load(group, name + "/weight", model.encoder->convolutions()[k]->weight);
    load(group, name + "/bias", model.encoder->convolutions()[k]->bias);
  }
  for (std::size_t k = 0; k < model.encoder->linears().size(); ++k) {
    const std::string name = "linear_" + std::to_string(k);
    load(group, name + "/weight", model.encoder->linears()[k]->weight);
    load(group, name + "/bias", model.encoder->linears()[k]->bias);
  }
  return particles;
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

TrainingRecord read_training(const io::hdf5::Group& root, const MapArchitecture& architecture) {
  const io::hdf5::Group group = root.open_group("training");
  TrainingRecord record;
  record.sweep_dir = group.read_string_attribute("sweep_dir");
  record.parameter_names = group.read_strings_attribute("parameter_names");
  TrainingSettings& s = record.settings;
  s.architecture = architecture;
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
  const std::vector<std::int64_t> index = members.read_dataset<std::int64_t>("index", {m});
  const std::vector<std::int32_t> test = members.read_dataset<std::int32_t>("test", {m});
  const std::vector<double> values = members.read_dataset<double>("values", {m, p});
  const std::vector<std::string> snapshots = members.read_strings_attribute("snapshots");
  if (snapshots.size() != m) invalid(members, "group", "attribute snapshots must name " + std::to_string(m) + " files");
  for (std::uint64_t i = 0; i < m; ++i) {
    record.members.push_back({index[i], std::vector<double>(values.begin() + i * p, values.begin() + (i + 1) * p),
                              test[i] != 0, snapshots[i]});
  }
  return record;
}

}  // namespace

void write_tensor(io::hdf5::Group& group, const std::string& path, const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  const io::hdf5::Shape shape(values.sizes().begin(), values.sizes().end());
  group.write_dataset(path, shape, values.data_ptr<float>());
}

torch::Tensor read_tensor(const io::hdf5::Group& group, const std::string& path,
                          const std::vector<std::int64_t>& shape) {
  std::vector<float> values = group.read_dataset<float>(path, io::hdf5::Shape(shape.begin(), shape.end()));
  for (float value : values) {
    if (!std::isfinite(value))
      throw io::UnusableFileError(group.label() + ": dataset " + object_path(group, path) + ": not finite");
  }
  return torch::from_blob(values.data(), shape, torch::kFloat32).clone();
}

void write_model_groups(io::hdf5::Group& root, const RomModel& model) {
  root.write_attribute("romp_version", model.training.romp_version);
  root.write_attribute("commit", model.training.commit);
  root.write_attribute("latent", model.map->architecture().latent);
  write_map(root, *model.map);
  write_encoder(root, model);
  write_training(root, model.training);
}

RomModel read_model_groups(const io::hdf5::Group& root, const torch::Device& device) {
  RomModel model;
  const std::int64_t latent = read_in(root, "latent", 1, romp::rom::kMaxMapLatent);
  model.map = read_map(root, latent);
  const std::int64_t particles = read_encoder(root, model);
  model.training = read_training(root, model.map->architecture());
  model.training.particle_count = particles;
  model.training.romp_version = root.read_string_attribute("romp_version");
  model.training.commit = root.read_string_attribute("commit");
  model.to(device);
  return model;
}

void write_rom_model(const std::string& path, const RomModel& model) {
  io::write_versioned_file(path, kRomModelFileFormat, [&](io::hdf5::File& file) { write_model_groups(file, model); });
}

RomModel read_rom_model(const std::string& path, const torch::Device& device) {
  return read_model_groups(io::open_versioned_file(path, kRomModelFileFormat), device);
}

}  // namespace romp::nn::rom
