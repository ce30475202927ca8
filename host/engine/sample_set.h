// SampleSet: the sample material points of a reduced substep (hyper-reduction, ROM paper Sec. 3.2.2),
// drawn anew every substep, and their kinematics decoded from the map: what G2P updates and the
// projections read.
#pragma once

#include <cstdint>
#include <vector>

#include "host/engine/deformation_map.h"
#include "host/engine/quadrature_points.h"
#include "host/geometry/random.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"

namespace romp::engine {

class SampleSet {
 public:
  // `wanted` free points a substep (0 or ≥ the point count: every point), plus `boundary_samples` from
  // every Dirichlet group (the paper: "at least 5 material points from each kinematic boundary").
  SampleSet(const mpm::ParticleInit& reference, Index dirichlet_groups, Index wanted, int boundary_samples,
            std::uint64_t seed, int latent);

  // Takes this substep's samples and gathers their reference state. The samples of many substeps are
  // drawn at once, in the same order as one substep at a time, and uploaded together: a substep
  // uploads nothing but every rows_ahead()-th (and, with every point sampled, only the first).
  void draw(const Exec& exec, const ReferenceBody& reference);
  // Before a frame of `substeps` draws: makes sure their samples are on the device, uploading once (the rows
  // left and as many new ones as a frame needs, at least rows_ahead()) when fewer are left, so that the
  // frame's substeps upload nothing. The sequence of samples is draw()'s alone.
  void draw_ahead(const Exec& exec, Index substeps);
  // For a CUDA graph of a frame, whose substep k must find its samples at one place in every frame: after
  // draw_ahead, copies the frame's `substeps` rows to the front of a buffer of their own (one copy on the
  // device; every point: nothing) and takes them from the sequence as draws would. draw_staged(k) is then
  // draw() for the frame's substep k.
  void stage_frame(const Exec& exec, Index substeps);
  void draw_staged(const Exec& exec, const ReferenceBody& reference, Index substep);
  // Gives the last staged frame's samples back to the sequence (a failed capture ran none of them).
  void unstage_frame(Index substeps) {
    if (!every_point_) next_row_ -= substeps;
  }
  // Where stage_frame put the frame's rows (empty with every point sampled).
  Span<const std::int32_t> staged_rows() const { return frame_rows_.span(); }
  // The samples each substep draws.
  Index per_substep() const { return per_substep_; }
  // Substeps whose samples one upload holds.
  Index rows_ahead() const { return rows_ahead_; }
  // x = g(X; x̂), F = ∇_X g, ∂g/∂x̂ and v = (∂g/∂x̂) v̂ at the samples.
  void decode(const Exec& exec, const DeformationMap& map, Span<const float> xhat, Span<const float> vhat);

  Index count() const { return points_.count; }
  QuadraturePoints& points() { return points_; }
  const QuadraturePoints& points() const { return points_; }
  Vec3Planes<const float> X() const { return Vec3Planes<const float>(points_.X.data(), count()); }
  Vec3Planes<const float> x() const { return Vec3Planes<const float>(points_.x.data(), count()); }
  Mat3Planes<const float> F() const { return Mat3Planes<const float>(points_.F.data(), count()); }
  // The material point of each sample.
  Span<const std::int32_t> index() const { return current_; }
  // ∂g/∂x̂ at the samples (3 r planes), and scratch for g there (3 planes; the position projection's).
  Span<float> dg_dxhat() { return dg_dxhat_.span(); }
  Span<float> model_x() { return model_x_.span(); }

 private:
  // Sorted material point indices: gathers read memory forwards, and a projection's sums have one order.
  std::vector<std::int32_t> choose();
  void resize(const Exec& exec, Index m);

  Index points_total_, wanted_;
  int boundary_samples_, latent_;
  bool every_point_;
  Index per_substep_ = 0, rows_ahead_ = 1, next_row_ = 0, rows_drawn_ = 0, per_row_ = 0;
  std::vector<std::int32_t> rows_;                        // the rows uploaded last, as index_ holds them
  std::vector<std::int32_t> free_points_;                 // not in a Dirichlet group
  std::vector<std::vector<std::int32_t>> group_members_;  // per Dirichlet group
  geometry::Random random_;
  QuadraturePoints points_;
  DeviceBuffer<std::int32_t> index_;       // rows_drawn_ substeps' samples, a row each
  DeviceBuffer<std::int32_t> frame_rows_;  // stage_frame's rows
  // Takes the samples `rows` holds and gathers their reference state.
  void take(const Exec& exec, const ReferenceBody& reference, Span<const std::int32_t> rows);
  Span<const std::int32_t> current_;  // this substep's row
  DeviceBuffer<float> dg_dxhat_, model_x_;
};

}  // namespace romp::engine
