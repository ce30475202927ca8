// SnapshotWriter: header and frames into the .partial file, sidecar and PLY files beside it, the
// final rename, and reopening a .partial file for --resume.
#include "nn/io/snapshot_writer.h"

#include <cctype>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "kernels/core/error.h"
#include "nn/io/atomic_file.h"
#include "nn/io/ply_export.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/unusable_file_error.h"
#include "nn/io/xdmf.h"

namespace romp::io {
namespace {

// The sidecar lists every frame, so rewriting it after each one would cost O(frames²) bytes over a
// run (a 1000-frame run: about 1 GB). It is rewritten while the frame count is small and then about
// eight times per doubling: at most an eighth of a running run's frames are missing from it, and the
// total written stays near 16 × its final size. finish() always writes the complete one.
bool sidecar_due(std::int64_t frame_count) {
  if (frame_count <= 16) return true;
  std::int64_t step = 1;
  while (step * 16 <= frame_count) step *= 2;
  return frame_count % step == 0;
}

// The index in a "frame_NNNNNN.ply" or "NNNNNN" name, or -1 for any other name.
std::int64_t frame_index(const std::string& name, const std::string& prefix, const std::string& suffix) {
  if (name.size() != prefix.size() + 6 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return -1;
  }
  const std::string digits = name.substr(prefix.size(), 6);
  for (char c : digits) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
  }
  return std::stoll(digits);
}

// Removes the PLY files of frames >= first, so the PLY folder shows the same frames as the snapshot.
void remove_ply_frames_from(const std::string& snapshot_path, std::int64_t first) {
  const std::filesystem::path folder = std::filesystem::path(ply_frame_path(snapshot_path, 0)).parent_path();
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) return;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (frame_index(entry.path().filename().string(), "frame_", ".ply") >= first) {
      std::filesystem::remove(entry.path());
    }
  }
}

FieldMask selected_fields(FieldMask fields) {
  if (fields & ~kAllFields) {
    throw Error(
        fmt::format("snapshot: field mask {:#x} has bits beyond {}", fields, fmt::join(field_names(kAllFields), ", ")));
  }
  return fields | kFieldX;
}

hdf5::File create_snapshot(const std::string& path, const SnapshotHeader& header, FieldMask selection) {
  header.validate();
  if (xdmf_path(path) == path) {
    throw Error(fmt::format("snapshot {}: the path must not end in .xdmf (the sidecar's)", path));
  }
  const FieldMask fields = selected_fields(selection);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!folder.empty()) std::filesystem::create_directories(folder, error);
  if (error) {
    throw Error(fmt::format("snapshot {}: cannot create folder {}: {}", path, folder.string(), error.message()));
  }

  const std::uint64_t n = std::uint64_t(header.particle_count());
  hdf5::File file = hdf5::File::create(partial_path(path), "snapshot");
  write_format_attributes(file, kSnapshotFile);
  file.write_attribute("romp_version", header.romp_version);
  file.write_attribute("commit", header.commit);
  file.write_attribute("scene", header.scene);
  file.write_attribute("parameter_names", header.parameter_names);
  file.write_attribute("parameter_values", header.parameter_values);
  file.write_attribute("particle_count", std::int64_t(n));
  file.write_attribute("fields", field_names(fields));
  file.write_attribute("frame_count", std::int64_t(0));
  file.write_dataset("/particles/X", {n, 3}, planes_to_rows(header.X, 3));
  file.write_dataset("/particles/mass", {n}, header.mass);
  file.write_dataset("/particles/volume0", {n}, header.volume0);
  file.write_dataset("/particles/material", {n}, header.material);
  if (!header.group.empty()) file.write_dataset("/particles/group", {n}, header.group);
  std::vector<std::int32_t> id(n);
  for (std::uint64_t p = 0; p < n; ++p) id[p] = std::int32_t(p);
  file.write_dataset("/particles/id", {n}, id);
  file.create_group("/frames");
  file.flush();
  return file;
}

template <class T>
Span<const T> span_of(const std::vector<T>& values) {
  return Span<const T>(values.data(), Index(values.size()));
}

}  // namespace

SnapshotWriter::SnapshotWriter(std::string path, const SnapshotHeader& header, FieldMask fields, bool ply)
    : SnapshotWriter(path, create_snapshot(path, header, fields), header, fields, ply, {}) {}

SnapshotWriter::SnapshotWriter(std::string path, hdf5::File file, const SnapshotHeader& header, FieldMask fields,
                               bool ply, std::vector<double> times)
    : path_(std::move(path)),
      file_(std::move(file)),
      fields_(selected_fields(fields)),
      ply_(ply),
      particle_count_(header.particle_count()),
      material_(header.material),
      has_group_(!header.group.empty()),
      times_(std::move(times)) {
  if (ply_) remove_ply_frames_from(path_, frame_count());
  write_sidecar(partial_path(path_));
}

SnapshotWriter SnapshotWriter::resume(std::string path, const SnapshotHeader& header, FieldMask selection,
                                      std::int64_t frame_count, bool ply) {
  header.validate();
  const FieldMask fields = selected_fields(selection);
  const std::string partial = partial_path(path);
  const std::string label = "snapshot " + partial;
  std::vector<double> times;
  {
    const SnapshotReader reader(partial);
    if (reader.particle_count() != header.particle_count()) {
      throw UnusableFileError(fmt::format("{}: holds {} particles, this run has {}; it belongs to another run", label,
                                          reader.particle_count(), header.particle_count()));
    }
    if (reader.fields() != fields) {
      throw UnusableFileError(fmt::format("{}: holds the fields {}, this run writes {}", label,
                                          fmt::join(field_names(reader.fields()), ", "),
                                          fmt::join(field_names(fields), ", ")));
    }
    if (reader.header().scene != header.scene) {
      throw UnusableFileError(label +
                              ": was written for another scene; remove it (or run without --resume) to start over");
    }
    if (reader.header().parameter_names != header.parameter_names ||
        reader.header().parameter_values != header.parameter_values) {
      throw UnusableFileError(label + ": was written with other parameter values; remove it to start over");
    }
    if (frame_count < 0 || frame_count > reader.frame_count()) {
      throw UnusableFileError(
          fmt::format("{}: holds {} complete frames, the resume needs {}", label, reader.frame_count(), frame_count));
    }
    times.assign(reader.frame_times().begin(), reader.frame_times().begin() + frame_count);
  }

  hdf5::File file = hdf5::File::open(partial, hdf5::Mode::ReadWrite, "snapshot");
  // Drop every later frame group, complete or not (a crash may have left one half written).
  hdf5::Group frames = file.open_group("/frames");
  for (const std::string& name : frames.list()) {
    const std::int64_t index = frame_index(name, "", "");
    if (index < 0) throw UnusableFileError(fmt::format("{}: group /frames/{} is not a frame", label, name));
    if (index >= frame_count) frames.remove(name);
  }
  file.write_attribute("frame_count", frame_count);
  file.flush();
  return SnapshotWriter(std::move(path), std::move(file), header, fields, ply, std::move(times));
}

void SnapshotWriter::append_frame(const FrameData& frame) {
  if (!file_) throw Error(fmt::format("snapshot {}: append_frame after finish()", path_));
  const std::int64_t k = frame_count();
  if (k >= kMaxFrames) throw Error(fmt::format("snapshot {}: more than {} frames", path_, kMaxFrames));
  const std::uint64_t n = std::uint64_t(particle_count_);
  // Check everything before writing anything, so a bad frame leaves no half-written group.
  for (const FieldInfo& info : kFieldInfos) {
    if ((fields_ & info.bit) && frame.field(info.bit).size() != info.components * n) {
      throw Error(fmt::format("snapshot {}: frame {}: field {} has {} values, expected {} ({} planes of {} particles)",
                              path_, k, info.name, frame.field(info.bit).size(), info.components * n, info.components,
                              n));
    }
  }

  hdf5::Group group = file_->create_group(frame_group_name(k));
  group.write_attribute("time", frame.time);
  group.write_attribute("step", frame.step);
  for (const FieldInfo& info : kFieldInfos) {
    if (!(fields_ & info.bit)) continue;
    group.write_dataset(info.name, field_shape(info, n), planes_to_rows(frame.field(info.bit), info.components));
  }
  if (frame.totals) {
    const FrameTotals& totals = *frame.totals;
    group.write_attribute("kinetic_energy", totals.kinetic_energy);
    group.write_attribute("elastic_energy", totals.elastic_energy);
    group.write_attribute("gravitational_energy", totals.gravitational_energy);
    group.write_attribute("linear_momentum",
                          std::vector<double>(totals.linear_momentum.begin(), totals.linear_momentum.end()));
    group.write_attribute("angular_momentum",
                          std::vector<double>(totals.angular_momentum.begin(), totals.angular_momentum.end()));
  }
  // Raised last: readers trust frames below frame_count only.
  file_->write_attribute("frame_count", k + 1);
  file_->flush();
  // On disk before the caller writes the checkpoint that counts this frame, also across a power loss.
  sync_file(partial_path(path_));
  times_.push_back(frame.time);
  if (sidecar_due(k + 1)) write_sidecar(partial_path(path_));

  if (ply_) {
    PlyPoints points;
    points.x = span_of(frame.x);
    if (fields_ & kFieldV) points.v = span_of(frame.v);
    points.material = span_of(material_);
    write_ply(ply_frame_path(path_, k), points,
              fmt::format("romp frame {} time {:.17g} step {}", k, frame.time, frame.step));
  }
}

void SnapshotWriter::finish() {
  if (!file_) throw Error(fmt::format("snapshot {}: finish() called twice", path_));
  file_->close();
  file_.reset();
  rename_durably(partial_path(path_), path_);
  write_sidecar(path_);
}

void SnapshotWriter::write_sidecar(const std::string& hdf5_path) const {
  XdmfSnapshot sidecar;
  sidecar.hdf5_file = std::filesystem::path(hdf5_path).filename().string();
  sidecar.particle_count = particle_count_;
  sidecar.fields = fields_;
  sidecar.has_group = has_group_;
  sidecar.frame_times = times_;
  write_xdmf(xdmf_path(path_), sidecar);
}

}  // namespace romp::io
