// materials/: the fixed corotated model (Stomakhin et al. 2012): energy, stress P, analytic dP
// through the differential of the polar rotation. Isotropic; ignores fibers and damage.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// Psi = mu |F - R|^2 + lambda/2 (J - 1)^2, R the rotation of the polar decomposition F = R S.
struct FixedCorotated {
  static constexpr Model kModel = Model::FixedCorotated;
  static constexpr const char* kName = "fixed_corotated";
  static constexpr bool kHasFiberStiffness = false;
  static constexpr bool kDegradedByDamage = false;
  static constexpr int kCodimension = 0;
  static constexpr bool kClosedFormKirchhoff = false;

  // mu, lambda are the Lame parameters of (E, nu) as make_material sets them.
  static void map_parameters(MaterialParams*, Real, Real) {}

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);

  // P = 2 mu (F - R) + lambda (J - 1) cof F.
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);

  // dP = 2 mu (dF - dR) + lambda (cof F : dF) cof F + lambda (J - 1) d(cof F), with dR from
  // polar_rotation_differential (below).
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);
};

// Differential of the polar rotation R(F) along dF. With S = R^T F (symmetric) and
// W = R^T dR (skew), R^T dF = W S + dS, so W S + S W = K := R^T dF - (R^T dF)^T. For the
// axial vectors (W = [w]x), W S + S W = [(tr S I - S) w]x, hence w = (tr S I - S)^{-1} k;
// in 2D this reads w = k / tr S. The matrix has eigenvalues s_i + s_j (i != j, signed singular
// values), singular only where R itself is not unique. dR = R W.
template <int Dim>
Mat<Dim> polar_rotation_differential(const Mat<Dim>& F, const Mat<Dim>& R, const Mat<Dim>& dF);

}  // namespace tear
