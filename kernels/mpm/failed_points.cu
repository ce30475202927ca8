// note_failed_points: a thread per note, one launch a substep.
#include "kernels/mpm/failed_points.h"

#include <cstring>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {
namespace {

struct NoteFailedPoint {
  FailedPointNotes notes;

  ROMP_HD void operator()(Index n) const {
    const FailedPointNote& note = notes[std::size_t(n)];
    const std::int64_t p = note.slot[0];
    if (p == kNoFailure) return;
    const PointSource& source = note.source;
    note.record[0] = !source.particles ? -1 : source.particle.empty() ? p : std::int64_t(source.particle[p]);
    const Vec3<float> x = source.x.load(p), X = source.X.load(p);
    float* floats = reinterpret_cast<float*>(note.record.data() + 1);
    for (int a = 0; a < 3; ++a) {
      floats[a] = x[a];
      floats[3 + a] = X[a];
    }
  }
};

}  // namespace

FailedPoint read_failed_point(Span<const std::int64_t> record) {
  ROMP_CHECK(record.size() == kFailedPointWords, "a failed point's record holds kFailedPointWords words");
  float floats[6];
  std::memcpy(floats, record.data() + 1, sizeof floats);
  return {record[0], Vec3<float>(floats[0], floats[1], floats[2]), Vec3<float>(floats[3], floats[4], floats[5])};
}

void note_failed_points(const Exec& exec, const FailedPointNotes& notes, int count) {
  ROMP_CHECK(count >= 0 && count <= kMostFailedPointNotes,
             "note_failed_points takes at most kMostFailedPointNotes notes");
  for (int n = 0; n < count; ++n)
    ROMP_CHECK(notes[std::size_t(n)].slot.size() == 1 && notes[std::size_t(n)].record.size() == kFailedPointWords,
               "a failed point's note needs one slot and a record of kFailedPointWords words");
  if (count > 0) for_each(exec, count, NoteFailedPoint{notes});
}

}  // namespace romp::mpm
