// MaterialParams, the plain-data material record the engine indexes per particle, and the dispatchers over its model.
//
// The engine keeps a small table of MaterialParams (one per material id) and calls the dispatchers
// below from its P2G / G2P functors, on either backend. MaterialParams is trivially copyable and
// holds every model's parameters in named fields (those a model does not use stay 0), so the table
// is a flat array that copies to the device as is. Dispatch is a switch on the model, never a
// virtual call: each case builds the small model struct from the record and calls it.
#pragma once

#include <cstdint>
#include <type_traits>

#include "kernels/core/hd.h"
#include "kernels/material/drucker_prager.h"
#include "kernels/material/fixed_corotated.h"
#include "kernels/material/hencky.h"
#include "kernels/material/host_evaluated.h"
#include "kernels/material/isotropic.h"
#include "kernels/material/lame.h"
#include "kernels/material/neo_hookean.h"
#include "kernels/material/plastic_return.h"
#include "kernels/material/stretch_clamp.h"
#include "kernels/material/von_mises.h"
#include "kernels/material/weakly_compressible_fluid.h"
#include "kernels/math/mat3.h"

namespace romp::material {

enum class MaterialModel : std::uint8_t {
  FixedCorotated,
  NeoHookean,
  HenckyStVK,
  DruckerPrager,  // sand: HenckyStVK + Drucker-Prager return map
  VonMises,       // plasticine: HenckyStVK + von Mises return map
  WeaklyCompressibleFluid,
  // A learned law whose stress and return map the host evaluates (host_evaluated.h); μ and λ are the
  // law's linearisation at rest, for the CFL condition's wave speed only.
  Neural,
};

template <class T>
struct MaterialParams {
  MaterialModel model;
  T mu;              // μ; unused by WeaklyCompressibleFluid
  T lambda;          // λ
  T yield_stress;    // VonMises: τ_y (Pa)
  T friction_alpha;  // DruckerPrager: α = drucker_prager_alpha(friction angle)
  T cohesion;        // DruckerPrager: log-strain shift of the cone tip (drucker_prager.h)
  T min_stretch;     // stress, energy and δP see principal stretches raised to this floor (stretch_clamp.h); 0: off

  static constexpr MaterialParams fixed_corotated(Lame<T> lame) {
    return {MaterialModel::FixedCorotated, lame.mu, lame.lambda, T(0), T(0), T(0), T(0)};
  }
  static constexpr MaterialParams neo_hookean(Lame<T> lame) {
    return {MaterialModel::NeoHookean, lame.mu, lame.lambda, T(0), T(0), T(0), T(0)};
  }
  static constexpr MaterialParams hencky_stvk(Lame<T> lame) {
    return {MaterialModel::HenckyStVK, lame.mu, lame.lambda, T(0), T(0), T(0), T(0)};
  }
  static constexpr MaterialParams von_mises(Lame<T> lame, T yield_stress) {
    return {MaterialModel::VonMises, lame.mu, lame.lambda, yield_stress, T(0), T(0), T(0)};
  }
  // The friction angle in degrees, 0 ≤ φ < 90; α is computed here, once, rather than per particle.
  static MaterialParams drucker_prager(Lame<T> lame, T friction_angle_degrees, T cohesion) {
    return {MaterialModel::DruckerPrager,
            lame.mu,
            lame.lambda,
            T(0),
            drucker_prager_alpha(friction_angle_degrees),
            cohesion,
            T(0)};
  }
  // This record with inversion handling (stretch_clamp.h) at `floor`; not for the fluid, whose F
  // carries only a volume.
  constexpr MaterialParams with_min_stretch(T floor) const {
    MaterialParams clamped = *this;
    clamped.min_stretch = floor;
    return clamped;
  }
  static constexpr MaterialParams weakly_compressible_fluid(T lambda) {
    return {MaterialModel::WeaklyCompressibleFluid, T(0), lambda, T(0), T(0), T(0), T(0)};
  }
  // `at_rest`: the law's small-strain Lamé parameters (nn/nclaw/rest_stiffness.h).
  static constexpr MaterialParams neural(Lame<T> at_rest) {
    return {MaterialModel::Neural, at_rest.mu, at_rest.lambda, T(0), T(0), T(0), T(0)};
  }
};

static_assert(std::is_trivially_copyable_v<MaterialParams<float>>);
static_assert(sizeof(MaterialParams<float>) <= 7 * sizeof(float), "one record per material id, kept small");

// visitor(model) for the model struct that `params` describes.
template <class T, class Visitor>
ROMP_HD auto visit_model(const MaterialParams<T>& params, const Visitor& visitor) {
  switch (params.model) {
    case MaterialModel::FixedCorotated: return visitor(FixedCorotated<T>{params.mu, params.lambda});
    case MaterialModel::NeoHookean: return visitor(NeoHookean<T>{params.mu, params.lambda});
    case MaterialModel::HenckyStVK: return visitor(HenckyStVK<T>{params.mu, params.lambda});
    case MaterialModel::DruckerPrager:
      return visitor(DruckerPrager<T>{{params.mu, params.lambda}, params.friction_alpha, params.cohesion});
    case MaterialModel::VonMises: return visitor(VonMises<T>{{params.mu, params.lambda}, params.yield_stress});
    case MaterialModel::WeaklyCompressibleFluid: return visitor(WeaklyCompressibleFluid<T>{params.lambda});
    case MaterialModel::Neural: return visitor(HostEvaluated<T>{});
  }
  // MaterialParams come from the factories above and the host's scene reader, which only write
  // enumerators: a value outside the enum is a programming error.
  __builtin_unreachable();
}

namespace material_detail {

template <class T>
struct EnergyDensity {
  const Mat3<T>& F;
  template <class Model>
  ROMP_HD T operator()(const Model& model) const {
    return model.energy_density(F);
  }
};

template <class T>
struct FirstPiola {
  const Mat3<T>& F;
  template <class Model>
  ROMP_HD Mat3<T> operator()(const Model& model) const {
    return model.first_piola(F);
  }
};

template <class T>
struct FirstPiolaDifferential {
  const Mat3<T>& F;
  const Mat3<T>& dF;
  template <class Model>
  ROMP_HD Mat3<T> operator()(const Model& model) const {
    return model.first_piola_differential(F, dF);
  }
};

template <class T>
struct DefiniteStiffness {
  const Mat3<T>& F;
  template <class Model>
  ROMP_HD PrincipalStiffness<T> operator()(const Model& model) const {
    return isotropic_stiffness(model, F).definite();
  }
};

template <class T>
struct ProjectPlastic {
  const Mat3<T>& F_trial;
  template <class Model>
  ROMP_HD Mat3<T> operator()(const Model& model) const {
    if constexpr (Model::kPlastic)
      return model.project(F_trial);
    else
      return F_trial;
  }
};

template <class T>
struct PlasticReturnOf {
  const Mat3<T>& F_trial;
  template <class Model>
  ROMP_HD PlasticReturn<T> operator()(const Model& model) const {
    if constexpr (Model::kPlastic)
      return model.plastic_return(F_trial);
    else
      return {F_trial, T(0)};
  }
};

struct IsPlastic {
  template <class Model>
  ROMP_HD bool operator()(const Model&) const {
    return Model::kPlastic;
  }
};

}  // namespace material_detail

// ψ(F) per unit reference volume (at the clamped F when params.min_stretch > 0).
template <class T>
ROMP_HD T energy_density(const MaterialParams<T>& params, const Mat3<T>& F) {
  const Mat3<T> F_used = clamp_stretches(F, params.min_stretch);
  return visit_model(params, material_detail::EnergyDensity<T>{F_used});
}

// P(F) = ∂ψ/∂F (at the clamped F when params.min_stretch > 0).
template <class T>
ROMP_HD Mat3<T> first_piola(const MaterialParams<T>& params, const Mat3<T>& F) {
  const Mat3<T> F_used = clamp_stretches(F, params.min_stretch);
  return visit_model(params, material_detail::FirstPiola<T>{F_used});
}

// δP = ∂P/∂F : δF (at the clamped F when params.min_stretch > 0).
template <class T>
ROMP_HD Mat3<T> first_piola_differential(const MaterialParams<T>& params, const Mat3<T>& F, const Mat3<T>& dF) {
  const Mat3<T> F_used = clamp_stretches(F, params.min_stretch);
  return visit_model(params, material_detail::FirstPiolaDifferential<T>{F_used, dF});
}

// ∂P/∂F at F made positive semidefinite (PrincipalStiffness::definite, Teran et al. 2005), formed
// once so that it can be applied to many δF. Every model goes through its principal-space form
// (isotropic.h), also NeoHookean and the fluid, whose plain differential needs no SVD.
template <class T>
ROMP_HD PrincipalStiffness<T> definite_stiffness(const MaterialParams<T>& params, const Mat3<T>& F) {
  const Mat3<T> F_used = clamp_stretches(F, params.min_stretch);
  return visit_model(params, material_detail::DefiniteStiffness<T>{F_used});
}

// The elastic F after the model's return map; F_trial itself for the elastic models.
template <class T>
ROMP_HD Mat3<T> project_plastic(const MaterialParams<T>& params, const Mat3<T>& F_trial) {
  return visit_model(params, material_detail::ProjectPlastic<T>{F_trial});
}

// project_plastic's F with the plastic strain the return map removed (0 for elastic models and the fluid).
template <class T>
ROMP_HD PlasticReturn<T> plastic_return(const MaterialParams<T>& params, const Mat3<T>& F_trial) {
  return visit_model(params, material_detail::PlasticReturnOf<T>{F_trial});
}

// Whether project_plastic can change F: the plastic models and the fluid (whose F is reset to its
// volume part). The engine builds its plasticity stage only when some material answers true.
ROMP_HD inline bool is_plastic(MaterialModel model) {
  MaterialParams<float> params{};
  params.model = model;
  return visit_model(params, material_detail::IsPlastic{});
}

}  // namespace romp::material
