// The named materials as scene materials (named_materials.h).
#include "host/scene/named_materials.h"

namespace romp::scene {

std::optional<NclawMaterial> nclaw_material_named(const std::string& name) {
  if (name == "jelly") return NclawMaterial::Jelly;
  if (name == "sand") return NclawMaterial::Sand;
  if (name == "plasticine") return NclawMaterial::Plasticine;
  if (name == "water") return NclawMaterial::Water;
  return std::nullopt;
}

scene::MaterialSpecification nclaw_preset(NclawMaterial which) {
  using material::MaterialModel;
  scene::MaterialSpecification m;
  m.density = 1e3;
  switch (which) {
    case NclawMaterial::Jelly:  // fixed corotated, E = 1e5, ν = 0.2, no plasticity
      m.name = "jelly";
      m.model = MaterialModel::FixedCorotated;
      m.youngs_modulus = 1e5;
      m.poissons_ratio = 0.2;
      break;
    case NclawMaterial::Sand:  // Hencky, E = 1e6, ν = 0.2, Drucker–Prager φ = 25°, no cohesion
      m.name = "sand";
      m.model = MaterialModel::DruckerPrager;
      m.youngs_modulus = 1e6;
      m.poissons_ratio = 0.2;
      m.friction_angle = 25.0;
      m.cohesion = 0.0;
      break;
    case NclawMaterial::Plasticine:  // Hencky, E = 3e5, ν = 0.25, von Mises τ_y = 5e3 Pa
      m.name = "plasticine";
      m.model = MaterialModel::VonMises;
      m.youngs_modulus = 3e5;
      m.poissons_ratio = 0.25;
      m.yield_stress = 5e3;
      break;
    case NclawMaterial::Water:  // τ = λ J (J − 1) I with λ of E = 1e5, ν = 0.3
      m.name = "water";
      m.model = MaterialModel::WeaklyCompressibleFluid;
      m.youngs_modulus = 1e5;
      m.poissons_ratio = 0.3;
      break;
  }
  return m;
}

}  // namespace romp::scene
