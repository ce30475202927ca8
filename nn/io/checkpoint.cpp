// Checkpoint files: versioned HDF5 files, written atomically, refused when damaged.
#include "nn/io/checkpoint.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/core/error.h"
#include "nn/io/versioned_file.h"

namespace romp::io {
namespace {

// A non-finite value in a checkpoint is damage (its checksums held, so it was written so): refused, not
// resumed from.
void require_finite(const hdf5::File& file, const char* name, const std::vector<float>& values) {
  const auto bad = std::find_if(values.begin(), values.end(), [](float value) { return !std::isfinite(value); });
  if (bad != values.end()) {
    throw UnusableFileError(fmt::format("{}: dataset /{}: value {} of {} is {}: not a state to resume from",
                                        file.label(), name, bad - values.begin(), values.size(), *bad));
  }
}

}  // namespace

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
  const FrameData& state = checkpoint.state;
  const std::uint64_t n = std::uint64_t(state.x.size() / 3);
  for (const FieldInfo& info : kFieldInfos) {
    if (!(info.bit & kStateFields)) continue;
    if (state.field(info.bit).size() != info.components * n) {
      throw Error(fmt::format("checkpoint {}: field {} has {} values, expected {} ({} planes of {} particles)", path,
                              info.name, state.field(info.bit).size(), info.components * n, info.components, n));
    }
  }
  write_versioned_file(path, kCheckpointFile, [&](hdf5::File& file) {
    file.write_attribute("particle_count", std::int64_t(n));
    file.write_attribute("frame", checkpoint.frame);
    file.write_attribute("time", state.time);
    file.write_attribute("step", state.step);
    file.write_attribute("tag", checkpoint.tag);
    for (const FieldInfo& info : kFieldInfos) {
      if (!(info.bit & kStateFields)) continue;
      file.write_dataset(info.name, {std::uint64_t(info.components), n}, state.field(info.bit));
    }
    // The plastic state where the run keeps one (absent from checkpoints of runs that keep none).
    for (const FieldInfo& info : kFieldInfos)
      if ((info.bit & kPlasticFields) && !state.field(info.bit).empty()) {
        if (state.field(info.bit).size() != n)
          throw Error(fmt::format("checkpoint {}: {} has {} values for {} particles", path, info.name,
                                  state.field(info.bit).size(), n));
        file.write_dataset(info.name, {1, n}, state.field(info.bit));
      }
    if (!checkpoint.corner_x.empty()) {
      if (checkpoint.corner_x.size() % 3 != 0)
        throw Error(
            fmt::format("checkpoint {}: corner_x has {} values, not 3 planes", path, checkpoint.corner_x.size()));
      if (checkpoint.particle_domain.size() != n)
        throw Error(fmt::format("checkpoint {}: particle_domain has {} entries for {} particles", path,
                                checkpoint.particle_domain.size(), n));
      file.write_dataset("corner_x", {3, std::uint64_t(checkpoint.corner_x.size() / 3)}, checkpoint.corner_x);
      file.write_dataset("particle_domain", {n}, checkpoint.particle_domain);
      file.write_attribute("domain_stiffening", double(checkpoint.domain_stiffening));
    }
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  const hdf5::File file = open_versioned_file(path, kCheckpointFile);
  const std::int64_t n = file.read_int64_attribute("particle_count");
  if (n < 0) throw UnusableFileError(fmt::format("{}: particle_count {} is negative", file.label(), n));
  Checkpoint checkpoint;
  checkpoint.frame = file.read_int64_attribute("frame");
  checkpoint.state.time = file.read_double_attribute("time");
  checkpoint.state.step = file.read_int64_attribute("step");
  checkpoint.tag = file.read_string_attribute("tag");
  for (const FieldInfo& info : kFieldInfos) {
    if (!(info.bit & kStateFields)) continue;
    checkpoint.state.field(info.bit) =
        file.read_dataset<float>(info.name, {std::uint64_t(info.components), std::uint64_t(n)});
    require_finite(file, info.name, checkpoint.state.field(info.bit));
  }
  for (const FieldInfo& info : kFieldInfos)
    if ((info.bit & kPlasticFields) && file.is_dataset(info.name)) {
      checkpoint.state.field(info.bit) = file.read_dataset<float>(info.name, {1, std::uint64_t(n)});
      require_finite(file, info.name, checkpoint.state.field(info.bit));
    }
  if (checkpoint.state.Jp.empty() != checkpoint.state.plastic_strain.empty())
    throw UnusableFileError(fmt::format("{}: holds one of Jp and plastic_strain without the other", file.label()));
  // A run writes a checkpoint only after a finite frame: anything else is not a state to resume from.
  if (!std::isfinite(checkpoint.state.time) || checkpoint.state.time < 0.0 || checkpoint.frame < 0 ||
      checkpoint.state.step < 0) {
    throw UnusableFileError(fmt::format("{}: time {}, frame {}, step {}: not a state a run writes", file.label(),
                                        checkpoint.state.time, checkpoint.frame, checkpoint.state.step));
  }
  if (file.is_dataset("corner_x")) {
    const hdf5::Shape shape = file.dataset_shape("corner_x");
    if (shape.size() != 2 || shape[0] != 3)
      throw UnusableFileError(fmt::format("{}: corner_x must be [3, corners]", file.label()));
    checkpoint.corner_x = file.read_dataset<float>("corner_x", shape);
    require_finite(file, "corner_x", checkpoint.corner_x);
    checkpoint.particle_domain = file.read_dataset<std::int32_t>("particle_domain", {std::uint64_t(n)});
    checkpoint.domain_stiffening = float(file.read_double_attribute("domain_stiffening"));
  }
  return checkpoint;
}

}  // namespace romp::io
