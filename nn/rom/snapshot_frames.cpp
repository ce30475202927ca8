// Snapshot file → tensors, through the one snapshot reader.
#include "nn/rom/snapshot_frames.h"

#include <fmt/format.h>

#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"
#include "nn/io/unusable_file_error.h"

namespace romp::nn::rom {
namespace {

// `components` planes of n particles → [n, components] rows.
torch::Tensor rows(const std::vector<float>& planes, std::int64_t n, std::int64_t components) {
  return torch::from_blob(const_cast<float*>(planes.data()), {components, n}, torch::kFloat32).t().contiguous();
}

}  // namespace

SnapshotFrames read_snapshot_frames(const std::string& path) {
  const io::SnapshotReader reader(path);
  if (!(reader.fields() & io::kFieldF))
    throw io::UnusableFileError(
        fmt::format("snapshot {}: attribute /fields lacks \"F\": ROM training needs x and F per frame (set "
                    "the scene's output.fields)",
                    path));
  if (reader.frame_count() < 1) throw io::UnusableFileError(fmt::format("snapshot {}: no complete frame", path));

  const std::int64_t n = reader.particle_count();
  SnapshotFrames s;
  s.X = rows(reader.header().X, n, 3);
  std::vector<torch::Tensor> x, F;
  for (std::int64_t k = 0; k < reader.frame_count(); ++k) {
    const io::FrameData frame = reader.read_frame(k);
    s.times.push_back(frame.time);
    x.push_back(rows(frame.x, n, 3));
    F.push_back(rows(frame.F, n, 9).view({n, 3, 3}));  // plane 3 i + j holds F_ij
  }
  s.x = torch::stack(x);
  s.F = torch::stack(F);
  return s;
}

}  // namespace romp::nn::rom
