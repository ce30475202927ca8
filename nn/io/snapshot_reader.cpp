// SnapshotReader: format checks, header arrays back to planes, frames on demand.
#include "nn/io/snapshot_reader.h"

#include <fmt/format.h>

#include "kernels/core/error.h"

namespace romp::io {

// What is wrong with the file's content is an invalid input (UnusableFileError: romp exits 3), as
// damage to the file is. A run's .partial file may be open for writing meanwhile: the writer flushes after
// each frame and raises frame_count last, so the frames below it read whole.
SnapshotReader::SnapshotReader(const std::string& path) : file_(open_versioned_file(path, kSnapshotFile)) {
  const std::int64_t n = file_.read_int64_attribute("particle_count");
  if (n < 0) throw UnusableFileError(fmt::format("{}: particle_count {} is negative", file_.label(), n));
  const std::uint64_t count = std::uint64_t(n);
  const std::vector<std::string> field_list = file_.read_strings_attribute("fields");
  try {
    fields_ = parse_fields(field_list);
  } catch (const Error& error) {
    throw UnusableFileError(file_.label() + ": attribute /fields: " + error.what());
  }

  header_.romp_version = file_.read_string_attribute("romp_version");
  header_.commit = file_.read_string_attribute("commit");
  header_.scene = file_.read_string_attribute("scene");
  header_.parameter_names = file_.read_strings_attribute("parameter_names");
  header_.parameter_values = file_.read_doubles_attribute("parameter_values");
  if (header_.parameter_names.size() != header_.parameter_values.size()) {
    throw UnusableFileError(fmt::format("{}: {} parameter_names but {} parameter_values", file_.label(),
                                        header_.parameter_names.size(), header_.parameter_values.size()));
  }
  header_.X = rows_to_planes(file_.read_dataset<float>("/particles/X", {count, 3}), 3);
  header_.mass = file_.read_dataset<float>("/particles/mass", {count});
  header_.volume0 = file_.read_dataset<float>("/particles/volume0", {count});
  header_.material = file_.read_dataset<std::int32_t>("/particles/material", {count});
  if (file_.exists("/particles/group")) header_.group = file_.read_dataset<std::int32_t>("/particles/group", {count});

  const std::int64_t frames = file_.read_int64_attribute("frame_count");
  if (frames < 0 || frames > kMaxFrames) {
    throw UnusableFileError(fmt::format("{}: frame_count {} is outside [0, {}]", file_.label(), frames, kMaxFrames));
  }
  times_.reserve(std::size_t(frames));
  steps_.reserve(std::size_t(frames));
  for (std::int64_t k = 0; k < frames; ++k) {
    const hdf5::Group group = file_.open_group(frame_group_name(k));
    times_.push_back(group.read_double_attribute("time"));
    steps_.push_back(group.read_int64_attribute("step"));
  }
}

void SnapshotReader::check_frame(std::int64_t frame) const {
  if (frame < 0 || frame >= frame_count()) {
    throw Error(fmt::format("{}: frame {} does not exist ({} frames)", file_.label(), frame, frame_count()));
  }
}

double SnapshotReader::frame_time(std::int64_t frame) const {
  check_frame(frame);
  return times_[std::size_t(frame)];
}

std::int64_t SnapshotReader::frame_step(std::int64_t frame) const {
  check_frame(frame);
  return steps_[std::size_t(frame)];
}

FrameData SnapshotReader::read_frame(std::int64_t frame) const {
  check_frame(frame);
  const std::uint64_t n = std::uint64_t(particle_count());
  const std::string group = frame_group_name(frame);
  FrameData data;
  data.time = times_[std::size_t(frame)];
  data.step = steps_[std::size_t(frame)];
  for (const FieldInfo& info : kFieldInfos) {
    if (!(fields_ & info.bit)) continue;
    data.field(info.bit) =
        rows_to_planes(file_.read_dataset<float>(group + "/" + info.name, field_shape(info, n)), info.components);
  }
  const hdf5::Group frame_group = file_.open_group(group);
  if (frame_group.has_attribute("kinetic_energy")) {
    FrameTotals totals;
    totals.kinetic_energy = frame_group.read_double_attribute("kinetic_energy");
    totals.elastic_energy = frame_group.read_double_attribute("elastic_energy");
    totals.gravitational_energy = frame_group.read_double_attribute("gravitational_energy");
    for (const auto& [name, vector] : {std::pair{"linear_momentum", &totals.linear_momentum},
                                       std::pair{"angular_momentum", &totals.angular_momentum}}) {
      const std::vector<double> values = frame_group.read_doubles_attribute(name);
      if (values.size() != 3)
        throw UnusableFileError(
            fmt::format("{}: {}/{} holds {} values, not 3", file_.label(), group, name, values.size()));
      std::copy(values.begin(), values.end(), vector->begin());
    }
    data.totals = totals;
  }
  return data;
}

}  // namespace romp::io
