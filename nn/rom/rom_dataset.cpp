// Sweep folder → training tensors: the manifest, each member's frames, the split and the encoder's points.
#include "nn/rom/rom_dataset.h"

#include <ATen/CPUGeneratorImpl.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/snapshot_frames.h"

namespace romp::nn::rom {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSweepFormat = "romp-sweep";
constexpr std::int64_t kSweepFormatVersion = 1;

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

nlohmann::json read_manifest(const std::string& label, const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw io::UnusableFileError(label + ": no " + path.filename().string() +
                                " (a folder written by romp sweep holds one)");
  nlohmann::json manifest;
  try {
    in >> manifest;
  } catch (const nlohmann::json::exception& error) {
    throw io::UnusableFileError(label + ": " + path.filename().string() + ": not valid JSON: " + error.what());
  }
  if (manifest.value("format", std::string()) != kSweepFormat)
    throw io::UnusableFileError(label + ": manifest.json: format is not \"" + kSweepFormat + "\"");
  const std::int64_t version = manifest.value("format_version", std::int64_t(0));
  if (version < 1 || version > kSweepFormatVersion) {
    throw io::UnusableFileError(label + ": manifest.json: format_version " + std::to_string(version) +
                                " is not one this romp reads (1 .. " + std::to_string(kSweepFormatVersion) + ")");
  }
  return manifest;
}

SweepMember parse_member(const nlohmann::json& entry, const std::vector<std::string>& names) {
  SweepMember member;
  member.index = entry.at("index").get<std::int64_t>();
  for (const std::string& name : names) member.values.push_back(entry.at("values").at(name).get<double>());
  const std::string split = entry.at("split").get<std::string>();
  if (split != "train" && split != "test")
    throw io::UnusableFileError("split is \"" + split + "\", expected \"train\" or \"test\"");
  member.test = split == "test";
  member.snapshot = entry.at("snapshot").get<std::string>();
  return member;
}

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

bool SweepMember::operator==(const SweepMember& other) const {
  return index == other.index && values == other.values && test == other.test && snapshot == other.snapshot;
}

RomDataset load_rom_dataset(const std::string& dir, const RomDatasetOptions& options) {
  const std::string label = "sweep " + dir;
  ROMP_CHECK(options.encoder_points >= 0, "encoder points must be >= 0 (0 = every point)");
  const nlohmann::json manifest = read_manifest(label, fs::path(dir) / "manifest.json");
  RomDataset data;
  data.dir = dir;
  try {
    data.parameter_names = manifest.at("parameters").get<std::vector<std::string>>();
    std::size_t position = 0;
    for (const nlohmann::json& entry : manifest.at("members")) {
      try {
        data.members.push_back(parse_member(entry, data.parameter_names));
      } catch (const std::exception& error) {
        // Named by its place in the list, not by its text: printing a hostile entry (an array nested
        // 200,000 deep) recurses as deep as it is nested and overflowed the stack.
        throw Error("members[" + std::to_string(position) + "] (a JSON " + entry.type_name() + "): " + error.what());
      }
      ++position;
    }
  } catch (const std::exception& error) {
    throw io::UnusableFileError(label + ": manifest.json: " + error.what());
  }
  if (data.members.empty()) throw io::UnusableFileError(label + ": manifest.json lists no members");

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
