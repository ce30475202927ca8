// read_ground_truth: snapshot frames into [frames, planes, n] tensors, scene into DiffMpmConfig.
#include "host/nclaw/ground_truth.h"

#include <fmt/format.h>

#include <cmath>

#include "host/scene/scene_parser.h"
#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/unusable_file_error.h"

namespace romp::nclaw {

nn::diffmpm::DiffMpmConfig differentiable_config(const scene::Scene& s, const std::string& label) {
  const auto require = [&](bool condition, const std::string& what) {
    if (!condition)
      throw io::UnusableFileError(
          fmt::format("{}: its scene {}; the differentiable step cannot reproduce it", label, what));
  };
  require(s.fixed_dt > 0.0, "has no fixed [time] dt");
  require(s.transfer == "apic", "uses transfer '" + s.transfer + "', not 'apic'");
  require(s.wall_friction == 0.0, "has wall friction " + std::to_string(s.wall_friction) + ", not 0");
  require(s.colliders.empty() && s.dirichlet.empty() && s.pokes.empty(), "has colliders, Dirichlet groups or pokes");
  nn::diffmpm::DiffMpmConfig config;
  static_cast<mpm::DomainConfig<double>&>(config) = s;
  return config;
}

namespace {

// Copies one field of every frame into a [frames, components, n] tensor.
torch::Tensor stack_field(const std::vector<io::FrameData>& frames, io::FieldMask field, int components) {
  const int64_t n = int64_t(frames.front().field(field).size()) / components;
  torch::Tensor out = torch::empty({int64_t(frames.size()), components, n}, torch::kFloat32);
  for (size_t k = 0; k < frames.size(); ++k)
    std::copy(frames[k].field(field).begin(), frames[k].field(field).end(), out[int64_t(k)].data_ptr<float>());
  return out;
}

torch::Tensor from_vector(const std::vector<float>& values) {
  return torch::tensor(c10::ArrayRef<float>(values), torch::kFloat32);
}

// Every value of `frame` finite and every position inside the domain's interior, [dx, cells dx − dx] per
// axis, where the differentiable step's stencil stays on its dense grid: a position outside (or NaN)
// would index nodes the grid does not have.
void check_frame(const io::FrameData& frame, int64_t k, const nn::diffmpm::DiffMpmConfig& config,
                 const std::string& label) {
  const std::size_t n = frame.x.size() / 3;
  for (const io::FieldMask field : {io::kFieldV, io::kFieldF, io::kFieldC}) {
    const std::vector<float>& values = frame.field(field);
    for (std::size_t e = 0; e < values.size(); ++e)
      if (!std::isfinite(values[e]))
        throw io::UnusableFileError(fmt::format("{}: frame {}, {} of particle {}: {} is not finite", label, k,
                                                io::field_names(field).front(), e % n, values[e]));
  }
  for (int a = 0; a < 3; ++a) {
    const double low = config.dx, high = double(config.domain_cells[std::size_t(a)] - 1) * config.dx;
    for (std::size_t p = 0; p < n; ++p) {
      const float x = frame.x[std::size_t(a) * n + p];
      if (!(x >= low && x <= high))
        throw io::UnusableFileError(
            fmt::format("{}: frame {}, particle {}: x[{}] = {} is outside the domain's interior [{:.6g}, {:.6g}] m "
                        "(or not finite)",
                        label, k, p, a, x, low, high));
    }
  }
}

}  // namespace

GroundTruth read_ground_truth(const std::string& path, int64_t last_frame) {
  const io::SnapshotReader reader(path);
  const std::string label = "ground truth " + path;
  const io::FieldMask needed = io::kFieldX | io::kFieldV | io::kFieldF | io::kFieldC;
  if ((reader.fields() & needed) != needed)
    throw io::UnusableFileError(label + ": frames must hold x, v, F and C (the scene's [output] fields), found " +
                                fmt::format("{}", fmt::join(io::field_names(reader.fields()), ", ")));
  const int64_t frames = last_frame < 0 ? reader.frame_count() : last_frame + 1;
  if (frames < 2 || frames > reader.frame_count())
    throw io::UnusableFileError(fmt::format("{}: needs frames 0 to {}, the file has {} complete frames", label,
                                            frames - 1, reader.frame_count()));

  GroundTruth truth;
  const scene::Scene scene = scene::parse_scene(reader.header().scene, path);
  truth.config = differentiable_config(scene, label);
  truth.materials = scene.materials;
  std::vector<io::FrameData> data;
  data.reserve(size_t(frames));
  for (int64_t k = 0; k < frames; ++k) {
    if (reader.frame_step(k) != k)
      throw io::UnusableFileError(
          fmt::format("{}: frame {} is after substep {}; training needs one frame per substep (frame_rate = 1/dt)",
                      label, k, reader.frame_step(k)));
    data.push_back(reader.read_frame(k));
    check_frame(data.back(), k, truth.config, label);
  }
  nn::nclaw::Trajectory& t = truth.trajectory;
  t.mass = from_vector(reader.header().mass);
  t.volume = from_vector(reader.header().volume0);
  t.x = stack_field(data, io::kFieldX, 3);
  t.v = stack_field(data, io::kFieldV, 3);
  t.C = stack_field(data, io::kFieldC, 9);
  t.F = stack_field(data, io::kFieldF, 9);
  t.validate();
  return truth;
}

}  // namespace romp::nclaw
