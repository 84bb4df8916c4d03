// materials/: the one list of constitutive models with their names and traits, and the dispatch
// from MaterialParams::model to a model's static functions. Knows no scene format.
#pragma once

#include <array>
#include <string>
#include <utility>

#include "tear/materials/fixed_corotated.h"
#include "tear/materials/neo_hookean.h"
#include "tear/materials/curve_qr.h"
#include "tear/materials/qr_aniso.h"
#include "tear/materials/stvk_hencky.h"
#include "tear/materials/surface_qr.h"

namespace tear {

// A model is a stateless struct of static members (tagged dispatch, no virtual calls):
//   kModel, kName           its `Model` value and its scene name
//   kHasFiberStiffness      uses kx, ky (the scene refuses a nonzero fiber_scale otherwise)
//   kDegradedByDamage       uses g (the scene refuses a damage block otherwise)
//   kClosedFormKirchhoff    has kirchhoff_stress<Dim>(m, F, D, g) = P F^T in closed form
//                           (else material.cpp forms first_piola times F^T)
//   kCodimension            0 for a solid; 1 (curve) or 2 (surface) for a codimensional model
//                           of Jiang et al. 2017, which works on an element's F (D unused) and
//                           has return_map<Dim>(m, F*) (its friction)
//   map_parameters(MaterialParams*, fiber_scale1, fiber_scale2), run after make_material has
//   set the Lame parameters; energy<Dim>(m, F, D, g), first_piola<Dim>(m, F, D, g) and
//   stress_differential<Dim>(m, F, D, dF, g) (analytic: the implicit integrator's Newton steps
//   need it exact), as the free functions of material.h.
// Plasticity is not a model: any model takes a return map on its F (plasticity.h).
// Adding a model: its file, its value in `Model` (material.h) and its entry in `Models`.
template <class... Ms>
struct ModelList {
  static constexpr int kCount = sizeof...(Ms);
};

using Models = ModelList<QrAniso, FixedCorotated, NeoHookean, StvkHencky, SurfaceQr, CurveQr>;

namespace registry_detail {

template <class... Ms>
constexpr bool listed_in_enum_order(ModelList<Ms...>) {
  int i = 0;
  bool ok = true;
  ((ok = ok && int(Ms::kModel) == i++), ...);
  return ok;
}

template <class Fn, class M, class... Ms>
auto visit(Model model, Fn& fn, ModelList<M, Ms...>) {
  if constexpr (sizeof...(Ms) == 0) {
    TEAR_ASSERT(model == M::kModel);
    return fn(M{});
  } else {
    if (model == M::kModel) return fn(M{});
    return visit(model, fn, ModelList<Ms...>{});
  }
}

}  // namespace registry_detail

// `Model` values are indices into `Models` (model_traits() relies on it).
static_assert(registry_detail::listed_in_enum_order(Models{}),
              "Models must list every Model value once, in the enum's order");

// fn(M{}) for the model struct M whose kModel is `model`: the one switch over models.
template <class Fn>
auto visit_model(Model model, Fn&& fn) {
  return registry_detail::visit(model, fn, Models{});
}

// The traits of one model as data, for code that holds a Model value (scene validation).
struct ModelTraits {
  Model model;
  const char* name;
  bool has_fiber_stiffness, degraded_by_damage, closed_form_kirchhoff;
  int codimension;
};

namespace registry_detail {

template <class... Ms>
constexpr std::array<ModelTraits, sizeof...(Ms)> traits_of(ModelList<Ms...>) {
  return {{ModelTraits{Ms::kModel, Ms::kName, Ms::kHasFiberStiffness, Ms::kDegradedByDamage,
                       Ms::kClosedFormKirchhoff, Ms::kCodimension}...}};
}

}  // namespace registry_detail

// Every registered model, in `Model` order.
inline constexpr std::array<ModelTraits, Models::kCount> kModelTraits =
    registry_detail::traits_of(Models{});

// The traits of `model`, which must be a registered value.
constexpr const ModelTraits& model_traits(Model model) { return kModelTraits[int(model)]; }

// The names of the registered models, in order, joined by ", "; with `trait`, only the models
// that have it (e.g. &ModelTraits::has_fiber_stiffness).
inline std::string model_names(bool ModelTraits::*trait = nullptr) {
  std::string out;
  for (const ModelTraits& t : kModelTraits) {
    if (trait && !(t.*trait)) continue;
    if (!out.empty()) out += ", ";
    out += t.name;
  }
  return out;
}

}  // namespace tear
