// SnapshotWriter: writes a run's snapshot frame by frame to "<path>.partial", keeps it readable after
// every frame (flushed, with an XDMF sidecar that points to it), and renames it to `path` when finished.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nn/io/hdf5_file.h"
#include "nn/io/snapshot_layout.h"

namespace romp::io {

// The sidecar xdmf_path(path) always points to the HDF5 file that exists: "<name>.partial" while the
// run writes (refreshed as frames arrive, see sidecar_due, so ParaView can open a running or crashed
// run), "<name>" once finish() has renamed it. romp_io takes no file locks, so viewers can read it meanwhile.
// Not thread-safe: one thread (normally the I/O worker) drives a writer.
class SnapshotWriter {
 public:
  // Starts a new snapshot: creates "<path>.partial" (replacing any), writes the header and the sidecar.
  // Frames carry `fields` (x is added). With `ply`, every frame k is also written to
  // ply_frame_path(path, k), and PLY frames an earlier run left in that folder are removed.
  SnapshotWriter(std::string path, const SnapshotHeader& header, FieldMask fields, bool ply = false);

  // Continues an interrupted run's "<path>.partial": checks that it was written for this header
  // (particle count, scene, parameters) with these fields, keeps frames 0 .. frame_count-1 and drops
  // later ones (and, with `ply`, their PLY files). The file must hold at least frame_count complete frames.
  static SnapshotWriter resume(std::string path, const SnapshotHeader& header, FieldMask fields,
                               std::int64_t frame_count, bool ply = false);

  SnapshotWriter(SnapshotWriter&&) = default;
  SnapshotWriter& operator=(SnapshotWriter&&) = delete;
  SnapshotWriter(const SnapshotWriter&) = delete;
  SnapshotWriter& operator=(const SnapshotWriter&) = delete;
  // Without finish() the .partial file is closed and kept, readable and resumable.
  ~SnapshotWriter() = default;

  // Appends frame frame_count(): writes the selected fields (each must hold its planes of
  // particle_count values), raises the file's frame_count, flushes to disk, refreshes the sidecar when due and,
  // when asked, writes the frame's PLY file.
  void append_frame(const FrameData& frame);

  // Closes the file, renames "<path>.partial" to `path` and points the sidecar at it.
  void finish();

  const std::string& path() const { return path_; }
  std::int64_t frame_count() const { return std::int64_t(times_.size()); }
  FieldMask fields() const { return fields_; }
  bool finished() const { return !file_.has_value(); }

 private:
  SnapshotWriter(std::string path, hdf5::File file, const SnapshotHeader& header, FieldMask fields, bool ply,
                 std::vector<double> times);

  void write_sidecar(const std::string& hdf5_path) const;

  std::string path_;
  std::optional<hdf5::File> file_;  // empty once finished
  FieldMask fields_;
  bool ply_;
  std::int64_t particle_count_;
  std::vector<std::int32_t> material_;  // for the PLY files
  bool has_group_;                      // /particles/group is written (the sidecar shows it)
  std::vector<double> times_;           // of the frames written, for the sidecar
};

}  // namespace romp::io
