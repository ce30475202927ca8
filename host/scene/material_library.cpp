// Scene materials as engine parameters, a learned law's included (material_library.h).
#include "host/scene/material_library.h"

#include "host/scene/toml_reader.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/rest_stiffness.h"

#include <fmt/format.h>

#include <cmath>

namespace romp::scene {

material::Lame<float> neural_law_at_rest(const std::string& law_file) {
  nn::nclaw::NeuralLaws laws = nn::nclaw::read_law_file(law_file).laws;
  laws.to(torch::kCPU, torch::kFloat64);
  const nn::nclaw::RestStiffness at_rest =
      nn::nclaw::rest_stiffness([&](const torch::Tensor& F) { return laws.elastic->forward(F); });
  // The CFL condition needs a positive wave speed; a law that is unstable at rest cannot be run.
  ROMP_CHECK(std::isfinite(at_rest.p_wave_modulus()) && at_rest.p_wave_modulus() > 0.0,
             fmt::format("{}: the elastic law's P-wave modulus at rest (lambda + 2 mu) is {} Pa; a usable law "
                         "resists compression (> 0)",
                         law_file, at_rest.p_wave_modulus()));
  return {float(at_rest.mu), float(at_rest.lambda)};
}

engine::MaterialSpec to_material_spec(const scene::MaterialSpecification& m) {
  using material::MaterialModel;
  using Params = material::MaterialParams<float>;
  const material::Lame<float> lame =
      material::lame_from_young_poisson(float(m.youngs_modulus), float(m.poissons_ratio));
  Params params{};
  switch (m.model) {
    case MaterialModel::FixedCorotated: params = Params::fixed_corotated(lame); break;
    case MaterialModel::NeoHookean: params = Params::neo_hookean(lame); break;
    case MaterialModel::HenckyStVK: params = Params::hencky_stvk(lame); break;
    case MaterialModel::VonMises: params = Params::von_mises(lame, float(m.yield_stress)); break;
    case MaterialModel::DruckerPrager:
      params = Params::drucker_prager(lame, float(m.friction_angle), float(m.cohesion));
      break;
    case MaterialModel::WeaklyCompressibleFluid: params = Params::weakly_compressible_fluid(lame.lambda); break;
    case MaterialModel::Neural: {
      // The parser checked only the file's format (scene_parser.cpp); the law itself is checked here,
      // with the error located where the scene names it.
      material::Lame<float> at_rest;
      try {
        at_rest = neural_law_at_rest(m.neural_law);
      } catch (const Error& error) {
        if (m.neural_law_source.empty()) throw;
        throw scene::SceneError(fmt::format("{}: {}", m.neural_law_source, error.what()));
      }
      return {Params::neural(at_rest), float(m.density), m.neural_law};
    }
  }
  if (m.model != MaterialModel::WeaklyCompressibleFluid) params = params.with_min_stretch(float(m.min_stretch));
  return {params, float(m.density), "", m.strength_off_from, m.strength_off_until};
}

engine::MaterialSpec nclaw_material(NclawMaterial which) { return to_material_spec(nclaw_preset(which)); }

}  // namespace romp::scene
