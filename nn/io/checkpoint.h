// Checkpoints for --resume: the full particle state at a frame, in a small HDF5 file of its own that
// is replaced atomically, so the one on disk is always complete.
//
// Layout: root attributes format = "romp-checkpoint", format_version = 1, particle_count, frame (i64),
// time (f64), step (i64), tag (string); datasets x [3,n], v [3,n], F [9,n], C [9,n] (f32, engine planes
// as they are: only romp reads this file). With particle domains, also corner_x [3, corners],
// particle_domain [n] (i32, kNoDomain where released) and the attribute domain_stiffening.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nn/io/snapshot_layout.h"

namespace romp::io {

inline constexpr FileFormat kCheckpointFile{"checkpoint", "romp-checkpoint", "a romp checkpoint", 1};

struct Checkpoint {
  // Time, step and all four fields (planes, particles in initial order), whatever the snapshot selects.
  FrameData state;
  // The snapshot frame this state is: frames 0 .. frame were appended before the checkpoint was
  // written, and a resumed run reopens the snapshot with SnapshotWriter::resume(..., frame + 1).
  std::int64_t frame = 0;
  // Opaque to io: what the runner checks before trusting the checkpoint (the resolved scene text).
  std::string tag;
  // The particle domains' state besides the particles (mpm::DomainInit): corner positions (3 planes),
  // each particle's domain (initial order), both empty without domains, and the last substep's stiffening.
  std::vector<float> corner_x;
  std::vector<std::int32_t> particle_domain;
  float domain_stiffening = 1.0f;
};

// Replaces `path` (normally checkpoint_path(snapshot)) with `checkpoint`. Write it after its frame has
// been appended to the snapshot.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Reads a checkpoint back bit for bit; errors name the file and what is wrong with it.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace romp::io
