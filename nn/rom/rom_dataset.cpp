// Sweep folder → training tensors: the manifest, each member's frames, the split and the encoder's points.
#include "nn/rom/rom_dataset.h"

#include <ATen/CPUGeneratorImpl.h>

#include <filesystem>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/snapshot_frames.h"

namespace romp::nn::rom {
namespace {

namespace fs = std::filesystem;

// Frames of one split before they become one tensor per field.
struct SetBuilder {
  std::vector<torch::Tensor> x, frame_velocity, F;
  std::vector<std::int64_t> next;
  std::vector<float> has_next, dt;

  std::int64_t size() const { return std::int64_t(next.size()); }

  SnapshotSet build(const torch::Device& device) const {
    SnapshotSet set;
    if (x.empty()) return set;
    set.x = torch::cat(x).to(device);
    set.frame_velocity = torch::cat(frame_velocity).to(device);
    set.F = torch::cat(F).to(device);
    set.next = torch::tensor(next, torch::kInt64).to(device);
    set.has_next = torch::tensor(has_next, torch::kFloat32).to(device);
    set.dt = torch::tensor(dt, torch::kFloat32).to(device);
    return set;
  }
};

// Appends every frame of one member to `set`; its reference positions must be X.
void add_member(const std::string& path, const SnapshotFrames& frames, const torch::Tensor& X, SetBuilder& set) {
  if (!torch::equal(frames.X, X)) {
    throw io::UnusableFileError("snapshot " + path +
                                ": its reference positions X differ from the first member's; the ROM needs "
                                "one reference configuration for the whole sweep");
  }
  const std::int64_t first = set.size();
  const std::int64_t count = std::int64_t(frames.times.size());
  for (std::int64_t k = 0; k < count; ++k) {
    const bool last = k + 1 == count;
    set.next.push_back(first + (last ? k : k + 1));
    set.has_next.push_back(last ? 0.0f : 1.0f);
    set.dt.push_back(last ? 1.0f : float(frames.times[k + 1] - frames.times[k]));
    if (!last && !(set.dt.back() > 0.0f))
      throw io::UnusableFileError("snapshot " + path + ": frame times do not increase at frame " +
                                  std::to_string(k + 1));
  }
  set.x.push_back(frames.x);
  torch::Tensor velocity = torch::zeros_like(frames.x);
  if (count > 1) {
    const torch::Tensor dt = torch::tensor(std::vector<float>(set.dt.end() - count, set.dt.end() - 1));
    velocity.slice(0, 0, count - 1) = (frames.x.slice(0, 1) - frames.x.slice(0, 0, count - 1)) / dt.view({-1, 1, 1});
  }
  set.frame_velocity.push_back(velocity);
  set.F.push_back(frames.F);
}

}  // namespace

RomDataset load_rom_dataset(const std::string& dir, const RomDatasetOptions& options) {
  const std::string label = "sweep " + dir;
  ROMP_CHECK(options.encoder_points >= 0, "encoder points must be >= 0 (0 = every point)");
  SweepManifest manifest = read_sweep_manifest(dir);
  RomDataset data;
  data.dir = dir;
  data.parameter_names = std::move(manifest.parameter_names);
  data.members = std::move(manifest.members);

  SetBuilder train, test;
  torch::Tensor X;
  for (const SweepMember& member : data.members) {
    try {
      const std::string path = (fs::path(dir) / member.snapshot).string();
      const SnapshotFrames frames = read_snapshot_frames(path);
      if (!X.defined()) X = frames.X;
      add_member(path, frames, X, member.test ? test : train);
    } catch (const io::UnusableFileError& error) {
      throw io::UnusableFileError(label + ": member " + std::to_string(member.index) + ": " + error.what());
    } catch (const std::exception& error) {  // the machine's fault (memory, a device): not the input's
      throw Error(label + ": member " + std::to_string(member.index) + ": " + error.what());
    }
  }
  if (train.x.empty())
    throw io::UnusableFileError(label + ": every member is in the test split; training needs at least one");

  const std::int64_t particles = X.size(0);
  data.X = X.to(options.device);
  if (options.encoder_points == 0 || options.encoder_points >= particles) {
    data.encoder_indices = torch::arange(particles, torch::kInt64);
  } else {
    auto generator = at::make_generator<at::CPUGeneratorImpl>(options.seed);
    data.encoder_indices =
        std::get<0>(torch::randperm(particles, generator, torch::kInt64).slice(0, 0, options.encoder_points).sort());
  }
  data.encoder_indices = data.encoder_indices.to(options.device);
  data.train = train.build(options.device);
  data.test = test.build(options.device);
  return data;
}

MapNormalisation RomDataset::normalisation() const {
  MapNormalisation n;
  n.X_min = std::get<0>(X.min(0));
  const torch::Tensor X_max = std::get<0>(X.max(0));
  const torch::Tensor extent = X_max - n.X_min;
  const torch::Tensor largest = extent.max();
  ROMP_CHECK(largest.item<double>() > 0.0, "sweep " + dir + ": every reference position is the same point");
  n.X_max = torch::where(extent > 0, X_max, n.X_min + largest);
  const auto [u_std, u_mean] = torch::std_mean((train.x - X).reshape({-1, 3}), {0}, /*unbiased=*/false);
  n.u_mean = u_mean;
  n.u_std = torch::max(u_std, largest * kMinDisplacementStd);
  return n;
}

}  // namespace romp::nn::rom
