// The snapshot file layout of DESIGN.md "Files": format names, per-frame fields, what a snapshot holds,
// the names of the files that go with it, and the change between engine planes and particle rows.
//
// A snapshot `out.h5` (while a run writes it: `out.h5.partial`) holds
//   root attributes  format = "romp-snapshot", format_version = 1, romp_version, commit,
//                    scene (the resolved scene text), parameter_names, parameter_values (μ, may be empty),
//                    particle_count, fields (names of the per-frame datasets, "x" first),
//                    frame_count (frames 0 .. frame_count-1 are complete; raised after each frame is written)
//   /particles/X [n,3] f32, mass [n] f32, volume0 [n] f32, material [n] i32,
//              id [n] i32 (0 .. n-1: the particles' initial order, and the sidecar's point topology),
//              group [n] i32 (Dirichlet group at t = 0, -1 for none; absent in files before it was written)
//   /frames/NNNNNN   (6-digit frame index) attributes time (f64, s) and step (i64), datasets among
//                    x [n,3], v [n,3], F [n,3,3], C [n,3,3], stress [n,3,3], J [n], von_mises [n],
//                    energy_density [n], Jp [n], plastic_strain [n] (f32, one row per particle, F[p][i][j] = F_ij);
//                    with the totals (FrameTotals) also the attributes kinetic_energy, elastic_energy,
//                    gravitational_energy (f64, J) and linear_momentum, angular_momentum (3 × f64, kg m/s and kg m²/s)
// Beside it: `out.xdmf` (ParaView), `out.h5.checkpoint` (resume), `out_ply/frame_NNNNNN.ply` (Blender, Houdini).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nn/io/versioned_file.h"

namespace romp::io {

inline constexpr FileFormat kSnapshotFile{"snapshot", "romp-snapshot", "a romp snapshot", 1};
// Frame groups are named with six digits, so name order is frame order.
inline constexpr std::int64_t kMaxFrames = 1000000;

// Per-frame fields, combined as a bit mask. Positions are always written.
using FieldMask = std::uint32_t;
inline constexpr FieldMask kFieldX = 1u << 0;  // position (m)
inline constexpr FieldMask kFieldV = 1u << 1;  // velocity (m/s)
inline constexpr FieldMask kFieldF = 1u << 2;  // elastic deformation gradient
inline constexpr FieldMask kFieldC = 1u << 3;  // affine velocity (1/s)
// What a state implies, computed from it for output (host/analysis/frame_outputs.h):
inline constexpr FieldMask kFieldStress = 1u << 4;         // Cauchy stress σ = P Fᵀ / det F (Pa)
inline constexpr FieldMask kFieldJ = 1u << 5;              // det F, the elastic volume ratio
inline constexpr FieldMask kFieldVonMises = 1u << 6;       // √(3/2 s:s) of σ's deviator s (Pa)
inline constexpr FieldMask kFieldEnergyDensity = 1u << 7;  // ψ(F), J per m³ of reference volume
// The plastic state, kept where a scene has a plastic material (mpm::ParticleView::Jp):
inline constexpr FieldMask kFieldJp = 1u << 8;             // J_p, the volume ratio removed by return maps
inline constexpr FieldMask kFieldPlasticStrain = 1u << 9;  // Σ ‖Δε‖ of the return maps' Hencky strain
// The state every simulation continues from (what every checkpoint holds; the plastic state besides).
inline constexpr FieldMask kStateFields = kFieldX | kFieldV | kFieldF | kFieldC;
inline constexpr FieldMask kDerivedFields = kFieldStress | kFieldJ | kFieldVonMises | kFieldEnergyDensity;
inline constexpr FieldMask kPlasticFields = kFieldJp | kFieldPlasticStrain;
inline constexpr FieldMask kAllFields = kStateFields | kDerivedFields | kPlasticFields;

struct FieldInfo {
  FieldMask bit;
  const char* name;  // dataset name in a frame group
  int components;    // 1 for scalars, 3 for vectors, 9 for 3x3 matrices
};
inline constexpr std::array<FieldInfo, 10> kFieldInfos{{{kFieldX, "x", 3},
                                                        {kFieldV, "v", 3},
                                                        {kFieldF, "F", 9},
                                                        {kFieldC, "C", 9},
                                                        {kFieldStress, "stress", 9},
                                                        {kFieldJ, "J", 1},
                                                        {kFieldVonMises, "von_mises", 1},
                                                        {kFieldEnergyDensity, "energy_density", 1},
                                                        {kFieldJp, "Jp", 1},
                                                        {kFieldPlasticStrain, "plastic_strain", 1}}};

// A field's dataset shape in a frame group: [n], [n,3] or [n,3,3].
std::vector<std::uint64_t> field_shape(const FieldInfo& info, std::uint64_t n);

// The mask of field names (as a scene's output.fields lists them, from kFieldInfos), with x added.
FieldMask parse_fields(const std::vector<std::string>& names);
// The names of the fields in `fields`, in kFieldInfos order.
std::vector<std::string> field_names(FieldMask fields);

// One frame in engine layout: component-major planes (x = [x0..xn-1, y0..yn-1, z0..zn-1], matrices as
// nine planes, plane 3*row+col), particles in their initial order. A field not selected stays empty.
// A frame's sums over its particles, in double (host/analysis/frame_outputs.h says how each is taken).
struct FrameTotals {
  double kinetic_energy = 0.0, elastic_energy = 0.0, gravitational_energy = 0.0;  // J
  std::array<double, 3> linear_momentum{}, angular_momentum{};                    // kg m/s, kg m²/s (about 0)
};

struct FrameData {
  double time = 0.0;      // s
  std::int64_t step = 0;  // substeps taken so far
  std::vector<float> x, v, F, C;
  std::vector<float> stress, J, von_mises, energy_density;
  std::vector<float> Jp, plastic_strain;  // empty where no plastic state is kept
  std::optional<FrameTotals> totals;

  std::vector<float>& field(FieldMask bit);
  const std::vector<float>& field(FieldMask bit) const;
};

// What a snapshot records once: the initial particles (engine layout) and where they came from.
struct SnapshotHeader {
  std::vector<float> X;  // reference positions, 3 planes
  std::vector<float> mass, volume0;
  std::vector<std::int32_t> material;
  std::vector<std::int32_t> group;  // Dirichlet group at t = 0 (mpm::kNoDirichletGroup = -1); may be empty
  std::string scene;                // the resolved scene text
  std::vector<std::string> parameter_names;
  std::vector<double> parameter_values;  // μ, one value per name
  std::string romp_version, commit;

  std::int64_t particle_count() const { return std::int64_t(mass.size()); }
  // Throws romp::Error when the arrays disagree on the particle count or the parameters on their number.
  void validate() const;
};

// "/frames/000012".
std::string frame_group_name(std::int64_t frame);
// "<path>.partial": where a run writes until it finishes.
std::string partial_path(const std::string& snapshot_path);
// "<path>.checkpoint": the state a run resumes from.
std::string checkpoint_path(const std::string& snapshot_path);
// "<folder>/<stem>.xdmf" for "<folder>/<stem>.h5".
std::string xdmf_path(const std::string& snapshot_path);
// "<folder>/<stem>_ply/frame_000012.ply" for "<folder>/<stem>.h5".
std::string ply_frame_path(const std::string& snapshot_path, std::int64_t frame);

// Engine planes [components][n] to particle rows [n][components], and back.
std::vector<float> planes_to_rows(const std::vector<float>& planes, int components);
std::vector<float> rows_to_planes(const std::vector<float>& rows, int components);

}  // namespace romp::io
