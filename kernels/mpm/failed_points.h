// A failure slot (mpm::Stage's, a domain check's) names a point by its place in the buffers of the substep
// that failed. Where substeps run on without reading their slots back (a reduced frame, read back once),
// later substeps reuse those buffers before the host looks: note_failed_points copies what a report says
// of the point, its particle and where it is, into a record beside the slot, in the substep that failed.
#pragma once

#include <array>
#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/vec3.h"

namespace romp::mpm {

// The points a slot indexes.
struct PointSource {
  Vec3Planes<const float> x;  // where they are now
  Vec3Planes<const float> X;  // where they are in the reference configuration
  // Each point's particle (empty: point i is particle i), unless `particles` is false: the points are
  // none (Eulerian quadrature points), reported as particle −1.
  Span<const std::int32_t> particle;
  bool particles = true;
};

// A record: [particle | x as 3 floats | X as 3 floats] in int64 words; its first word stays as it was reset
// (kNoFailure) while its slot is empty.
inline constexpr int kFailedPointWords = 4;

struct FailedPointNote {
  Span<const std::int64_t> slot;  // one slot: kNoFailure, or the point's index in `source`
  PointSource source;
  Span<std::int64_t> record;  // kFailedPointWords
};

// What a record holds, read on the host.
struct FailedPoint {
  std::int64_t particle = 0;
  Vec3<float> x, X;
};
FailedPoint read_failed_point(Span<const std::int64_t> record);

// One launch for up to kMostFailedPointNotes notes: each copies its point when its slot names one.
inline constexpr int kMostFailedPointNotes = 4;
using FailedPointNotes = std::array<FailedPointNote, kMostFailedPointNotes>;
void note_failed_points(const Exec& exec, const FailedPointNotes& notes, int count);

}  // namespace romp::mpm
