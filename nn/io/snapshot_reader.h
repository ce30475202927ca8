// SnapshotReader: opens a finished snapshot or a run's .partial file, checks that it is a romp snapshot
// this build reads, and returns its header and frames in engine layout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_layout.h"

namespace romp::io {

class SnapshotReader {
 public:
  // Reads the header and the frame times; frames are read on demand. Throws romp::Error naming the
  // file (and the object) when it is not a readable romp snapshot.
  explicit SnapshotReader(const std::string& path);

  const std::string& path() const { return file_.filename(); }
  const SnapshotHeader& header() const { return header_; }
  std::int64_t particle_count() const { return header_.particle_count(); }
  // The fields every frame holds (x among them).
  FieldMask fields() const { return fields_; }
  // Complete frames; a crashed run's file may hold a later, unfinished frame group, which is ignored.
  std::int64_t frame_count() const { return std::int64_t(times_.size()); }
  const std::vector<double>& frame_times() const { return times_; }
  double frame_time(std::int64_t frame) const;
  std::int64_t frame_step(std::int64_t frame) const;

  // Frame `frame` in engine layout (planes, initial order); fields the file lacks stay empty.
  FrameData read_frame(std::int64_t frame) const;

 private:
  void check_frame(std::int64_t frame) const;

  hdf5::File file_;
  SnapshotHeader header_;
  FieldMask fields_ = kFieldX;
  std::vector<double> times_;
  std::vector<std::int64_t> steps_;
};

}  // namespace romp::io
