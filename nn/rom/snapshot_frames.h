// The fields ROM training reads from a romp snapshot file, as tensors: the snapshot reader's frames
// (nn/io/snapshot_reader.h) turned from the engine's planes into per-particle rows.
#pragma once

#include <torch/torch.h>

#include <string>
#include <vector>

namespace romp::nn::rom {

// The complete frames of one snapshot, on the CPU, float32, particles in their initial order.
struct SnapshotFrames {
  torch::Tensor X;            // [P, 3] reference positions (/particles/X)
  torch::Tensor x;            // [T, P, 3] positions
  torch::Tensor F;            // [T, P, 3, 3], F[t][p][i][j] = F_ij
  std::vector<double> times;  // [T] s
};

// Reads every complete frame's x and F. Throws romp::Error naming the file (and the object) when it is
// not a romp snapshot, lacks F (the scene's output.fields), or holds no complete frame.
SnapshotFrames read_snapshot_frames(const std::string& path);

}  // namespace romp::nn::rom
