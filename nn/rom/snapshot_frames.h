// The fields ROM training reads from a romp snapshot file, straight into tensors. The file layout is the one
// host/io/snapshot_layout.h documents and host/io writes; nn/ may not use host/, so this reader follows that
// layout with nn's own HDF5 wrapper (the rows the file stores are already the tensors' layout).
#pragma once

#include <torch/torch.h>

#include <string>
#include <vector>

#include "nn/rom/versioned_file.h"

namespace romp::nn::rom {

// Matches io::kSnapshotFormat and io::kSnapshotFormatVersion (host/io/snapshot_layout.h).
inline constexpr FileFormat kSnapshotFileFormat{"snapshot", "romp-snapshot", "a romp snapshot", 1};

// The complete frames of one snapshot, on the CPU, float32, particles in their initial order.
struct SnapshotFrames {
  torch::Tensor X;             // [P, 3] reference positions (/particles/X)
  torch::Tensor x, v;          // [T, P, 3] positions and velocities
  torch::Tensor F;             // [T, P, 3, 3], F[t][p][i][j] = F_ij
  std::vector<double> times;   // [T] s
};

// Reads every complete frame's x, v and F. Throws romp::Error naming the file and the object when it is not a
// romp snapshot, lacks v or F (the scene's output.fields), or holds no complete frame.
SnapshotFrames read_snapshot_frames(const std::string& path);

}  // namespace romp::nn::rom
