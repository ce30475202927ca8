// Parameters of the named materials.
#include "host/material_library.h"

namespace romp {
namespace {

using Params = material::MaterialParams<float>;
constexpr float kNclawDensity = 1e3f;

}  // namespace

MaterialSpec nclaw_material(NclawMaterial which) {
  switch (which) {
    case NclawMaterial::Jelly:  // fixed corotated, E = 1e5, ν = 0.2, no plasticity
      return {Params::fixed_corotated(material::lame_from_young_poisson(1e5f, 0.2f)), kNclawDensity};
    case NclawMaterial::Sand:  // Hencky, E = 1e6, ν = 0.2, Drucker–Prager φ = 25°, no cohesion
      return {Params::drucker_prager(material::lame_from_young_poisson(1e6f, 0.2f), 25.0f, 0.0f), kNclawDensity};
    case NclawMaterial::Plasticine:  // Hencky, E = 3e5, ν = 0.25, von Mises τ_y = 5e3 Pa
      return {Params::von_mises(material::lame_from_young_poisson(3e5f, 0.25f), 5e3f), kNclawDensity};
    case NclawMaterial::Water:  // τ = λ J (J − 1) I with λ of E = 1e5, ν = 0.3
      return {Params::weakly_compressible_fluid(material::lame_from_young_poisson(1e5f, 0.3f).lambda), kNclawDensity};
  }
  return {};
}

}  // namespace romp
