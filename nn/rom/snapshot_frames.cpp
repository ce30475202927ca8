// Snapshot file → tensors: format checks, the reference positions and the x, v, F of every complete frame.
#include "nn/rom/snapshot_frames.h"

#include <fmt/format.h>

#include <algorithm>

#include "kernels/core/error.h"
#include "nn/hdf5_file.h"

namespace romp::nn::rom {
namespace {

// Frame groups are "/frames/NNNNNN" (six digits, io::frame_group_name).
std::string frame_group(std::int64_t frame) { return fmt::format("/frames/{:06d}", frame); }

torch::Tensor read_floats(const hdf5::Group& group, const std::string& path, const std::vector<std::int64_t>& shape) {
  std::vector<float> values = group.read_dataset<float>(path, hdf5::Shape(shape.begin(), shape.end()));
  return torch::from_blob(values.data(), shape, torch::kFloat32).clone();
}

}  // namespace

SnapshotFrames read_snapshot_frames(const std::string& path) {
  const hdf5::File file = open_versioned_file(path, kSnapshotFileFormat);
  const std::vector<std::string> fields = file.read_strings_attribute("fields");
  for (const char* needed : {"v", "F"}) {
    if (std::find(fields.begin(), fields.end(), needed) == fields.end()) {
      throw Error(fmt::format("{}: attribute /fields lacks \"{}\": ROM training needs x, v and F per frame (set the "
                              "scene's output.fields)",
                              file.label(), needed));
    }
  }
  const std::int64_t particles = file.read_int64_attribute("particle_count");
  if (particles < 1) throw Error(fmt::format("{}: attribute /particle_count is {}, expected >= 1", file.label(), particles));
  // Frames below frame_count are complete; a crashed run may leave a later, unfinished group, which is ignored.
  const std::int64_t frames = file.read_int64_attribute("frame_count");
  if (frames < 1) throw Error(fmt::format("{}: attribute /frame_count is {}: no complete frame", file.label(), frames));

  SnapshotFrames s;
  s.X = read_floats(file, "/particles/X", {particles, 3});
  std::vector<torch::Tensor> x, v, F;
  for (std::int64_t k = 0; k < frames; ++k) {
    const std::string group = frame_group(k);
    s.times.push_back(file.open_group(group).read_double_attribute("time"));
    x.push_back(read_floats(file, group + "/x", {particles, 3}));
    v.push_back(read_floats(file, group + "/v", {particles, 3}));
    F.push_back(read_floats(file, group + "/F", {particles, 3, 3}));
  }
  s.x = torch::stack(x);
  s.v = torch::stack(v);
  s.F = torch::stack(F);
  return s;
}

}  // namespace romp::nn::rom
