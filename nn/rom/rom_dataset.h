// Training data for the ROM: a sweep folder's manifest and member snapshots as tensors on the training device,
// split by parameter instance into train and test, with the material points the encoder reads.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

#include "nn/rom/deformation_map.h"
#include "nn/rom/sweep_manifest.h"

namespace romp::nn::rom {

// The snapshots of one split, member by member, frames in time order; P material points each, in the
// snapshots' initial particle order.
struct SnapshotSet {
  torch::Tensor x;  // [S, P, 3] f32 positions (m)
  // [S, P, 3] f32 (x_{n+1} − x_n) / (t_{n+1} − t_n) (m/s), 0 for a last frame: the velocity the frames imply,
  // which Eq. (31)'s velocity term matches with the same difference of x̂. Not the stored v_n: frames a few
  // substeps apart make their forward difference differ from v_n by O(Δt) (13.7 % on the gravity sweep,
  // 1/144 s apart), a gap no tangent ∂g/∂x̂ could close.
  torch::Tensor frame_velocity;
  torch::Tensor F;         // [S, P, 3, 3] f32 deformation gradients
  torch::Tensor next;      // [S] i64: the snapshot of frame n+1 of the same member, or itself for a last frame
  torch::Tensor has_next;  // [S] f32: 1 where frame n+1 exists, else 0
  torch::Tensor dt;        // [S] f32: t_{n+1} − t_n, 1 for a last frame (its rate x̂_{n+1} − x̂_n is 0)

  std::int64_t size() const { return x.defined() ? x.size(0) : 0; }
};

struct RomDatasetOptions {
  std::int64_t encoder_points = 1000;  // Q: material points in the encoder's input; every point if P ≤ Q or Q = 0
  std::uint64_t seed = 0;              // chooses those points
  torch::Device device = torch::kCPU;  // where every tensor lives
};

struct RomDataset {
  std::string dir;  // the sweep folder
  std::vector<std::string> parameter_names;
  std::vector<SweepMember> members;  // manifest order
  torch::Tensor X;                   // [P, 3] f32 reference positions, the same in every member
  torch::Tensor encoder_indices;     // [Q] i64, increasing: the points the encoder reads
  SnapshotSet train, test;

  std::int64_t particle_count() const { return X.size(0); }
  // The reference bounding box of X (an axis the body does not span gets the largest extent) and the mean and
  // standard deviation of the training displacements x − X per component (floored, see kMinDisplacementStd).
  MapNormalisation normalisation() const;
};

// Displacement components whose standard deviation is below this fraction of the body's size count as
// motionless; their standard deviation is raised to it so the standardised output stays finite.
inline constexpr double kMinDisplacementStd = 1e-6;

// Reads DIR/manifest.json (read_sweep_manifest) and every member's snapshot. The snapshots must hold x, v and F
// per frame and share one reference configuration X; at least one member must be for training. Throws
// romp::Error naming the folder, the member and the file.
RomDataset load_rom_dataset(const std::string& dir, const RomDatasetOptions& options);

}  // namespace romp::nn::rom
