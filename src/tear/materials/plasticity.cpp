#include "tear/materials/plasticity.h"

#include "tear/materials/helpers.h"
#include "tear/materials/material.h"
#include "tear/math/svd.h"

#include <cmath>

namespace tear {

PlasticParams von_mises(Real E, Real nu, Real yield_stress, Real hardening) {
  PlasticParams p;
  p.surface = YieldSurface::VonMises;
  p.mu = lame_mu(E, nu);
  p.lambda = lame_lambda(E, nu);
  p.yield_stress = yield_stress;
  p.hardening = hardening;
  return p;
}

PlasticParams drucker_prager(Real E, Real nu, Real friction_angle_deg, Real cohesion,
                             bool volume_correction) {
  PlasticParams p;
  p.surface = YieldSurface::DruckerPrager;
  p.mu = lame_mu(E, nu);
  p.lambda = lame_lambda(E, nu);
  const Real phi = friction_angle_deg * Real(M_PI / 180), s = std::sin(phi);
  const Real fit = std::sqrt(Real(2) / 3) / (3 - s);
  p.friction = fit * 2 * s;
  p.cohesion_term = fit * 6 * cohesion * std::cos(phi);
  p.volume_correction = volume_correction;
  return p;
}

namespace {

// F = U exp(diag(eps)) V^T: the Hencky strain on F's signed singular directions.
template <int Dim>
struct Hencky {
  Mat<Dim> U, V;
  Vec<Dim> eps;

  explicit Hencky(const Mat<Dim>& F) {
    Vec<Dim> sigma;
    signed_svd<Dim>(F, &U, &sigma, &V);
    for (int i = 0; i < Dim; ++i) eps[i] = safe_log(sigma[i]);
  }
  Mat<Dim> F(const Vec<Dim>& e) const {
    return U * e.array().exp().matrix().asDiagonal() * V.transpose();
  }
};

// The deviator of a principal strain.
template <int Dim>
Vec<Dim> deviator(const Vec<Dim>& eps) {
  return eps - Vec<Dim>::Constant(eps.sum() / Dim);
}

const Real kSqrt32 = std::sqrt(Real(1.5));

template <int Dim>
Real von_mises_excess(const PlasticParams& p, const Vec<Dim>& eps, const PlasticState& state) {
  return kSqrt32 * 2 * p.mu * deviator<Dim>(eps).norm() -
         (p.yield_stress + p.hardening * state.strain);
}

// Drucker-Prager: |dev tau| + friction tr(tau) - cohesion_term, tr(tau) = (Dim lambda + 2 mu) tr.
template <int Dim>
Real drucker_prager_excess(const PlasticParams& p, const Vec<Dim>& eps) {
  return 2 * p.mu * deviator<Dim>(eps).norm() +
         p.friction * (Dim * p.lambda + 2 * p.mu) * eps.sum() - p.cohesion_term;
}

// The strains projected onto each surface.
template <int Dim>
Vec<Dim> project_von_mises(const PlasticParams& p, const Vec<Dim>& eps,
                           const PlasticState& state) {
  const Real excess = von_mises_excess<Dim>(p, eps, state);
  if (excess <= 0) return eps;
  // The equivalent plastic strain increment of the radial return, exact because tau is linear
  // in eps: sqrt(3/2) 2 mu (|dev| - sqrt(3/2) d) = yield + H (strain + d).
  const Real d = excess / (3 * p.mu + p.hardening);
  const Vec<Dim> dev = deviator<Dim>(eps);
  return eps - (kSqrt32 * d / dev.norm()) * dev;
}

template <int Dim>
Vec<Dim> project_drucker_prager(const PlasticParams& p, const Vec<Dim>& eps) {
  const Real bulk = Dim * p.lambda + 2 * p.mu;  // tr(tau) per tr(eps)
  const Real apex = p.cohesion_term / (p.friction * bulk);
  // At or beyond the apex (expansion past the cohesion): no stress but the apex's.
  if (eps.sum() >= apex) return Vec<Dim>::Constant(apex / Dim);
  const Real excess = drucker_prager_excess<Dim>(p, eps);
  if (excess <= 0) return eps;
  // Shear back onto the cone at the same trace (here |dev| > 0, since tr < apex).
  const Vec<Dim> dev = deviator<Dim>(eps);
  return eps - (excess / (2 * p.mu) / dev.norm()) * dev;
}

}  // namespace

template <int Dim>
bool return_map(const PlasticParams& p, Mat<Dim>* F, PlasticState* state) {
  if (p.surface == YieldSurface::None) return false;
  const Hencky<Dim> h(*F);
  const bool dp = p.surface == YieldSurface::DruckerPrager, correct = dp && p.volume_correction;
  Vec<Dim> eps = h.eps;
  if (correct) eps.array() += state->volume / Dim;
  const Vec<Dim> out =
      dp ? project_drucker_prager<Dim>(p, eps) : project_von_mises<Dim>(p, eps, *state);
  state->strain += std::sqrt(Real(2) / 3) * (out - eps).norm();
  // The volume the apex took away is owed back; inside the cone or on its side it is all spent
  // (moved into F).
  if (correct) state->volume = eps.sum() - out.sum();
  if (out == h.eps) return false;
  *F = h.F(out);
  return true;
}

template <int Dim>
Real yield_function(const PlasticParams& p, const Mat<Dim>& F, const PlasticState& state) {
  const Hencky<Dim> h(F);
  switch (p.surface) {
    case YieldSurface::VonMises:
      return von_mises_excess<Dim>(p, h.eps, state);
    case YieldSurface::DruckerPrager:
      return drucker_prager_excess<Dim>(p, h.eps);
    case YieldSurface::None:
      break;
  }
  return -1;
}

template bool return_map<2>(const PlasticParams&, Mat<2>*, PlasticState*);
template bool return_map<3>(const PlasticParams&, Mat<3>*, PlasticState*);
template Real yield_function<2>(const PlasticParams&, const Mat<2>&, const PlasticState&);
template Real yield_function<3>(const PlasticParams&, const Mat<3>&, const PlasticState&);

}  // namespace tear
