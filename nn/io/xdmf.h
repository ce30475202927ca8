// The XDMF sidecar of a snapshot: an XML index that lets ParaView (Xdmf3 reader) open the HDF5 file
// as a point cloud over time, with every per-frame field and per-particle constant as point data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nn/io/snapshot_layout.h"

namespace romp::io {

struct XdmfSnapshot {
  // The HDF5 file the sidecar points to, relative to the sidecar's folder (the sidecar always lies
  // beside its snapshot, so this is the file name: "out.h5", or "out.h5.partial" while a run writes).
  std::string hdf5_file;
  std::int64_t particle_count = 0;
  FieldMask fields = kFieldX;
  bool has_group = false;           // /particles/group exists
  std::vector<double> frame_times;  // frame k at frame_times[k] (s)
};

// The XDMF 3 document: a temporal collection with one Polyvertex grid per frame. Each grid's geometry
// is /frames/NNNNNN/x; the other fields are Scalars, Vectors or Tensors ([n,3,3] read as 9
// components) by their shape; X, mass, volume0, material, group (when written) and id come from /particles.
std::string xdmf_document(const XdmfSnapshot& snapshot);

// Writes xdmf_document(snapshot) to `path` atomically.
void write_xdmf(const std::string& path, const XdmfSnapshot& snapshot);

}  // namespace romp::io
