// Drawing the samples and decoding their kinematics.
#include "host/engine/sample_set.h"

#include <algorithm>
#include <numeric>
#include <unordered_set>

#include "kernels/core/error.h"
#include "kernels/core/memory.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::engine {
namespace {

// k distinct members of `pool`, drawn uniformly (Floyd's algorithm: k draws, no pass over the pool).
std::vector<std::int32_t> draw_distinct(const std::vector<std::int32_t>& pool, std::size_t k,
                                        geometry::Random& random) {
  const std::size_t n = pool.size();
  if (k >= n) return pool;
  std::unordered_set<std::size_t> chosen;
  for (std::size_t j = n - k; j < n; ++j) {
    const std::size_t t = std::size_t(random.below(j + 1));
    chosen.insert(chosen.count(t) ? j : t);
  }
  std::vector<std::int32_t> members;
  for (const std::size_t i : chosen) members.push_back(pool[i]);
  return members;
}

}  // namespace

SampleSet::SampleSet(const mpm::ParticleInit& reference, Index dirichlet_groups, Index wanted, int boundary_samples,
                     std::uint64_t seed, int latent)
    : points_total_(reference.count()),
      wanted_(wanted),
      boundary_samples_(boundary_samples),
      latent_(latent),
      every_point_(wanted == 0 || wanted >= reference.count()),
      group_members_(std::size_t(dirichlet_groups)),
      random_(seed) {
  for (Index p = 0; p < points_total_; ++p) {
    const std::int32_t group = reference.dirichlet_group[std::size_t(p)];
    (group == mpm::kNoDirichletGroup ? free_points_ : group_members_[std::size_t(group)]).push_back(std::int32_t(p));
  }
  // Every substep draws as many: wanted free points, and from each group its share or all it has.
  per_substep_ = every_point_ ? points_total_ : std::min<Index>(wanted_, Index(free_points_.size()));
  if (!every_point_)
    for (const std::vector<std::int32_t>& members : group_members_)
      per_substep_ += std::min<Index>(boundary_samples_, Index(members.size()));
  // Up to 256 substeps in an upload of at most 2^20 indices (4 MiB); every point is one row for good.
  rows_ahead_ = every_point_ ? 1 : std::clamp<Index>((Index(1) << 20) / std::max<Index>(per_substep_, 1), 1, 256);
}

std::vector<std::int32_t> SampleSet::choose() {
  if (wanted_ == 0 || wanted_ >= points_total_) {
    std::vector<std::int32_t> all(static_cast<std::size_t>(points_total_));
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
  std::vector<std::int32_t> samples;
  for (const std::vector<std::int32_t>& members : group_members_) {
    const std::vector<std::int32_t> drawn = draw_distinct(members, std::size_t(boundary_samples_), random_);
    samples.insert(samples.end(), drawn.begin(), drawn.end());
  }
  const std::vector<std::int32_t> drawn = draw_distinct(free_points_, std::size_t(wanted_), random_);
  samples.insert(samples.end(), drawn.begin(), drawn.end());
  std::sort(samples.begin(), samples.end());
  return samples;
}

void SampleSet::resize(const Exec& exec, Index m) {
  if (points_.count == m) return;
  points_.allocate(exec.backend, m);
  dg_dxhat_ = DeviceBuffer<float>(exec.backend, 3 * Index(latent_) * m);
  model_x_ = DeviceBuffer<float>(exec.backend, 3 * m);
}

void SampleSet::draw_ahead(const Exec& exec, Index substeps) {
  if (every_point_ ? rows_drawn_ > 0 : rows_drawn_ - next_row_ >= substeps) return;
  // The rows left, then the next ones, each as one substep's choose() would give it, so the sequence is the
  // same however the draws are grouped.
  std::vector<std::int32_t> rows(rows_.begin() + next_row_ * per_row_, rows_.end());
  Index drawn = rows_drawn_ - next_row_;
  for (; drawn < (every_point_ ? 1 : std::max(rows_ahead_, substeps)); ++drawn) {
    const std::vector<std::int32_t> chosen = choose();
    per_row_ = Index(chosen.size());
    rows.insert(rows.end(), chosen.begin(), chosen.end());
  }
  index_.upload_front(exec.backend, rows, exec.stream);
  if (!every_point_) rows_ = std::move(rows);  // every point's one row is never drawn again
  rows_drawn_ = drawn;
  next_row_ = 0;
}

void SampleSet::draw(const Exec& exec, const ReferenceBody& reference) {
  draw_ahead(exec, 1);
  take(exec, reference, index_.span().subspan(next_row_ * per_row_, per_row_));
  if (!every_point_) ++next_row_;
}

void SampleSet::stage_frame(const Exec& exec, Index substeps) {
  ROMP_CHECK(every_point_ || rows_drawn_ - next_row_ >= substeps, "stage_frame: after draw_ahead for the frame");
  if (every_point_) return;
  const Index words = substeps * per_row_;
  frame_rows_.ensure_size(exec.backend, words);
  memory::copy(frame_rows_.data(), exec.backend, index_.data() + next_row_ * per_row_, exec.backend,
               std::size_t(words) * sizeof(std::int32_t), exec.stream);
  next_row_ += substeps;
}

void SampleSet::draw_staged(const Exec& exec, const ReferenceBody& reference, Index substep) {
  if (every_point_) {
    take(exec, reference, index_.prefix(per_row_));
    return;
  }
  ROMP_CHECK(frame_rows_.size() >= (substep + 1) * per_row_, "draw_staged: a substep of the staged frame");
  take(exec, reference, frame_rows_.span().subspan(substep * per_row_, per_row_));
}

void SampleSet::take(const Exec& exec, const ReferenceBody& reference, Span<const std::int32_t> rows) {
  resize(exec, rows.size());
  current_ = rows;
  reference.gather(exec, current_, points_);
}

void SampleSet::decode(const Exec& exec, const DeformationMap& map, Span<const float> xhat, Span<const float> vhat) {
  const Index m = count();
  map.evaluate(exec, xhat, X(),
               {Vec3Planes<float>(points_.x.data(), m), Mat3Planes<float>(points_.F.data(), m), dg_dxhat_.span()});
  rom::latent_to_point_velocity(exec, latent_, dg_dxhat_.span(), vhat, Vec3Planes<float>(points_.v.data(), m));
}

}  // namespace romp::engine
