// materials/: plasticity as a return map of the elastic deformation gradient F (the one F a
// particle carries; the plastic part is implied). Yield surfaces on the Kirchhoff stress of
// St. Venant-Kirchhoff with Hencky strain: von Mises with linear isotropic hardening, and
// Drucker-Prager with its apex and the volume correction of Tampubolon et al. 2017. Pure
// functions of F and a particle's plastic state; knows no grid.
#pragma once

#include "tear/math/types.h"

namespace tear {

enum class YieldSurface { None, VonMises, DruckerPrager };

// One material's plasticity, already mapped from the scene's (yield_stress, hardening) or
// (friction_angle, cohesion) and the material's (E, nu).
//
// Stress is measured as StVK-Hencky's Kirchhoff stress tau = U (2 mu eps + lambda tr(eps) I) U^T
// with eps = log Sigma (F = U Sigma V^T), mu and lambda the Lame parameters of (E, nu), whatever
// the elastic model: exact for stvk_hencky, the paper's choice for the others (its Fig. 14 heart
// is qr_aniso with this von Mises map). Damage does not enter: the map works on the undegraded
// (effective) stress, so in the degraded stress g(d) tau the yield surface shrinks with g(d).
struct PlasticParams {
  YieldSurface surface = YieldSurface::None;
  Real mu = 0, lambda = 0;
  // von Mises: sqrt(3/2) |dev tau| <= yield_stress + hardening * plastic_strain.
  Real yield_stress = 0, hardening = 0;
  // Drucker-Prager: |dev tau| + friction tr(tau) <= cohesion_term (the cone fitted to
  // Mohr-Coulomb in compression: friction = sqrt(2/3) 2 sin(phi) / (3 - sin(phi)),
  // cohesion_term = sqrt(2/3) 6 c cos(phi) / (3 - sin(phi))).
  Real friction = 0, cohesion_term = 0;
  // Drucker-Prager: remember the volume a particle gained while projected to the apex and
  // spend it on later compression before stress builds (Tampubolon et al. 2017, §4.3.1).
  bool volume_correction = true;
};

PlasticParams von_mises(Real E, Real nu, Real yield_stress, Real hardening = 0);
// friction_angle_deg in (0, 90); cohesion >= 0 (a stress).
PlasticParams drucker_prager(Real E, Real nu, Real friction_angle_deg, Real cohesion = 0,
                             bool volume_correction = true);

// A particle's plastic state.
struct PlasticState {
  // Accumulated equivalent plastic strain: the sum of sqrt(2/3) |delta eps_p| (Frobenius norm
  // of each step's change of the Hencky strain). Von Mises hardens with it.
  Real strain = 0;
  // Drucker-Prager with volume correction: log-volume gained at the apex not yet given back.
  Real volume = 0;
};

// Project F onto the yield surface (the closest point in Hencky strain for the stress norm
// above), updating `state`; F is unchanged inside the surface or with YieldSurface::None.
// Returns whether F was changed. F must have det F > 0 for a meaningful result; inverted or
// collapsed singular values are read through the floored log of the elastic models (helpers.h).
template <int Dim>
bool return_map(const PlasticParams& p, Mat<Dim>* F, PlasticState* state);

// The yield function at F (tau of the Hencky model as above): > 0 outside the surface, 0 on it,
// < 0 inside. For tests and diagnostics.
template <int Dim>
Real yield_function(const PlasticParams& p, const Mat<Dim>& F, const PlasticState& state);

}  // namespace tear
