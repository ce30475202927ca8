// ParticleSet: the structure-of-arrays particle state of a full-order simulation, and its kernel view.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/mpm/domain_init.h"

namespace romp::mpm {

inline constexpr std::int32_t kNoDirichletGroup = -1;
inline constexpr std::int32_t kNoTraction = -1;

// What kernels see: planes and spans, no ownership.
struct ParticleView {
  Index count = 0;
  Vec3Planes<float> x;                 // position (m)
  Vec3Planes<float> v;                 // velocity (m/s)
  Mat3Planes<float> C;                 // affine velocity / velocity gradient (1/s)
  Mat3Planes<float> F;                 // elastic deformation gradient
  Span<float> mass;                    // kg
  Span<float> volume0;                 // reference volume (m^3)
  Span<std::int32_t> material;         // index into the step's material table
  Span<std::int32_t> dirichlet_group;  // index into the step's prescribed motions, or kNoDirichletGroup
  Span<std::int32_t> id;               // index of the particle in the initial state (sorting permutes the arrays)
  Span<std::int32_t> domain;           // the particle's hexahedral domain, or kNoDomain; empty when no particle has one
  // The plastic state, kept where a scene has a plastic material (empty otherwise): J_p, the volume
  // ratio the return maps removed (Π det F_trial / det F), and the plastic strain accumulated by them
  // (Σ ‖Δε‖, material::PlasticReturn).
  Span<float> Jp, plastic_strain;
  // The surface traction a particle carries (index into StepParams::tractions), or kNoTraction; empty
  // when the scene has none.
  Span<std::int32_t> traction;

  // Particles with a domain exchange with the grid through its corners (particle_domains.h), not
  // through their own stencil.
  ROMP_HD bool has_domain(Index p) const { return !domain.empty() && domain[p] != kNoDomain; }
};

// Host-side description of the initial particles (planes as in ParticleView). F and C may be left
// empty (F = I, C = 0); a resumed run fills them from its checkpoint.
struct ParticleInit {
  std::vector<float> x, v;  // 3 planes each
  std::vector<float> F, C;  // 9 planes each, or empty
  std::vector<float> mass, volume0;
  std::vector<std::int32_t> material, dirichlet_group;
  std::vector<std::int32_t> domain;  // per particle: index into `domains`, or kNoDomain; empty when none has one
  // J_p then the plastic strain (2 planes) when the plastic state is kept (ParticleView), else empty.
  std::vector<float> plastic;
  std::vector<std::int32_t> traction;  // per particle: index into the tractions, or kNoTraction; empty when none
  DomainInit domains;
  Index count() const { return Index(mass.size()); }
};

// ParticleSet::sort_by_block's working storage, kept between sorts so that a sort allocates nothing
// after the first (on CUDA an allocation synchronises the device). The particle arrays are gathered into
// spares of their two allocations in one launch, and the two swap.
struct BlockSortScratch {
  DeviceBuffer<std::uint64_t> keys, sorted_keys, unique_keys;
  DeviceBuffer<std::int32_t> order, sorted_order, run_lengths;
  DeviceBuffer<std::int64_t> run_count;
  DeviceBuffer<unsigned char> temporary;  // CUB's
  DeviceBuffer<float> reals;
  DeviceBuffer<std::int32_t> integers;
};

class ParticleSet {
 public:
  ParticleSet(Backend backend, const ParticleInit& init);

  ParticleView view();
  Index count() const { return count_; }
  Backend backend() const { return backend_; }
  std::size_t bytes() const;

  // How sort_by_block learns how many runs of particles (blocks) it found: read back, so that the launches
  // over the runs are sized to them, or left on the device, so that the sort makes no round trip (a CUDA graph
  // can hold it) and those launches run over the particle count, a bound, whose runs past the count are empty.
  // With the count on the device the sorted particles are also copied back into the buffers they came from
  // (two device copies) rather than swapped with the sort's: a graph of substeps that sort then ends with the
  // particles where it found them, ready for its next replay.
  enum class RunCount { ReadBack, OnDevice };
  // Reorders the particles by the grid block that holds their stencil's base node, so neighbours in
  // memory are neighbours in space. CUDA: a stable radix sort on the block key. CPU: by block, then
  // by initial index, so the order is a function of the positions alone and a run resumed from a
  // checkpoint sums particle contributions in the same order as the uninterrupted run.
  void sort_by_block(const Exec& exec, float inverse_dx, RunCount run_count = RunCount::ReadBack);
  // After sort_by_block: where each block's run of particles starts, then the particle count (runs + 1
  // entries, non-decreasing; with RunCount::OnDevice, n + 1 entries, those past the runs equal to n, i.e. empty
  // runs). The tiled P2G gives each run to one worker.
  Span<const std::int32_t> block_starts() const {
    return Span<const std::int32_t>(block_starts_.data(), block_bound_ + 1);
  }
  // After sort_by_block: each particle's block key as that sort found it (increasing), until the next sort.
  Span<const std::uint64_t> sorted_block_keys() const { return sort_scratch_.keys.prefix(count_); }

  // A copy of the particle state, to go back to (FullOrderSim's batches of substeps roll back to their start when
  // a substep broke the CFL step they were planned with). Sized by the first save; two device copies after.
  struct Snapshot {
    DeviceBuffer<float> reals;
    DeviceBuffer<std::int32_t> integers;
  };
  void save(const Exec& exec, Snapshot& snapshot) const;
  void restore(const Exec& exec, const Snapshot& snapshot);

  // The particles of Dirichlet group `group` move freely from now on.
  void release_dirichlet_group(const Exec& exec, std::int32_t group);

  // Copies of the state in the order of the initial particles (undoing sort_by_block).
  std::vector<float> positions_in_initial_order(const Exec& exec) const;
  std::vector<float> velocities_in_initial_order(const Exec& exec) const;
  std::vector<float> deformation_gradients_in_initial_order(const Exec& exec) const;
  std::vector<float> affine_velocities_in_initial_order(const Exec& exec) const;
  // J_p and the plastic strain (2 planes), or empty when the plastic state is not kept.
  std::vector<float> plastic_state_in_initial_order(const Exec& exec) const;
  // Each particle's domain index (kNoDomain once released); empty when no particle had one.
  std::vector<std::int32_t> domains_in_initial_order(const Exec& exec) const;

 private:
  template <class T>
  std::vector<T> planes_in_initial_order(const Exec& exec, Span<const T> planes, int components) const;

  // The particle arrays as planes of count_ in two allocations, so that one launch permutes them all
  // (the sort's gathers were ten launches: the step's largest share of launches in small scenes).
  // Real planes: x (3), v (3), C (9), F (9), mass, volume0, and J_p and the plastic strain where the
  // plastic state is kept; integer planes: material, Dirichlet group, id, then the domain where a
  // particle has one and the traction where the scene has some (domain_plane_, traction_plane_).
  enum RealPlane : int {
    kX = 0,
    kV = 3,
    kC = 6,
    kF = 15,
    kMass = 24,
    kVolume0 = 25,
    kRealPlanes = 26,
    kJp = 26,
    kPlasticStrain = 27,
    kPlasticRealPlanes = 28
  };
  enum IntegerPlane : int { kMaterial = 0, kDirichletGroup = 1, kId = 2, kFixedIntegerPlanes = 3 };
  Span<float> reals(int first, int planes) {
    return reals_.span().subspan(Index(first) * count_, Index(planes) * count_);
  }
  Span<const float> reals(int first, int planes) const {
    return reals_.span().subspan(Index(first) * count_, Index(planes) * count_);
  }
  Span<std::int32_t> integers(int plane) { return integers_.span().subspan(Index(plane) * count_, count_); }
  Span<const std::int32_t> integers(int plane) const { return integers_.span().subspan(Index(plane) * count_, count_); }
  bool has_domains() const { return domain_plane_ >= 0; }
  bool has_plastic_state() const { return reals_.size() > Index(kRealPlanes) * count_; }

  Backend backend_;
  Index count_;
  DeviceBuffer<float> reals_;
  DeviceBuffer<std::int32_t> integers_;
  int domain_plane_ = -1, traction_plane_ = -1;  // their integer planes, or -1 when absent
  DeviceBuffer<std::int32_t> block_starts_;
  Index block_bound_ = 0;  // the runs the last sort found, or the particle count where they stayed on the device
  BlockSortScratch sort_scratch_;
};

}  // namespace romp::mpm
