// What a frame's state implies, computed for output on the I/O worker: the derived per-particle fields
// a scene may select (io::kDerivedFields: Cauchy stress, J, von Mises stress, energy density) and the
// frame's totals (energies and momenta), from x, v, F, C and the particles' constants.
#pragma once

#include <cstdint>
#include <vector>

#include "host/engine/sim_config.h"
#include "kernels/material/material.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/particle_set.h"
#include "nn/io/snapshot_layout.h"

namespace romp::run {

class FrameOutputs {
 public:
  // `particles`: mass, volume0 and material of every particle in the initial order (the frames' order).
  // Throws romp::Error naming output.fields when a selected field needs an energy or a stress that a
  // material does not define in closed form (a learned law), or a plastic state the particles do not keep.
  FrameOutputs(io::FieldMask fields, const engine::FullOrderConfig& config, const mpm::ParticleInit& particles);

  // Fills the selected derived fields and the totals of `frame` (whose x, v and F are filled; C too
  // for the APIC spin term). Totals, summed in double:
  //   kinetic_energy = Σ ½ m |v|²; elastic_energy = Σ V₀ ψ(F) (NaN when a material is a learned law,
  //   which has no energy); gravitational_energy = −Σ m g·x (zero at the origin);
  //   linear_momentum = Σ m v; angular_momentum about the origin = Σ m (x × v + D ε:Cᵀ) with APIC's
  //   inertia D = Δx²/4 of the quadratic B-spline (the particles' own spin; 0 for PIC/FLIP), the
  //   quantity APIC transfers conserve (Jiang et al. 2015).
  void add_to(io::FrameData& frame) const;

 private:
  io::FieldMask fields_;
  std::vector<material::MaterialParams<float>> materials_;
  bool learned_law_ = false;
  Vec3<double> gravity_;
  double affine_inertia_;
  std::vector<float> mass_, volume0_;
  std::vector<std::int32_t> material_;
};

}  // namespace romp::run
