// materials/: the QR-based elastoplastic curve of Jiang et al. 2017 (supplement §3 in 3D, §5 in
// 2D): yarn and hair, a segment element whose F = [d1 d2 (d3)] D^-1 has the segment as its first
// column and grid-advected normals as the others. Energy, stress, dP and the frictional return
// map. Knows nothing of particles.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// With F = Q R, R = [[r11, r^T], [0, Rh]] (r the shear of the normals against the curve, Rh the
// cross-section: 3D [[r22, r23], [0, r33]], r = (r12, r13); 2D the scalar r22, r = r12):
//   Psi = E/2 (r11 - 1)^2 + gamma/2 |r|^2 + h(J),  J = det Rh,
//   h(J) = s/3 (1 - J)^3 (J < 1), 0 otherwise,
// E the stretch modulus, gamma = shear_stiffness, s = normal_stiffness. h depends on the cross
// section's area alone, so its Kirchhoff stress there is the pressure p I, p = J h'(J) <= 0
// (supplement §3 takes just this dilational part of a 2x2 Drucker-Prager sand); layers that
// separate pull nothing. In the Q basis, with cof(Rh) = J Rh^-T:
//   Q^T P = [[E (r11 - 1), gamma r^T], [(gamma Rh r - h' cof(Rh) r) / r11, h' cof(Rh)]].
struct CurveQr {
  static constexpr Model kModel = Model::CurveQr;
  static constexpr const char* kName = "curve_qr";
  static constexpr bool kHasFiberStiffness = false;
  static constexpr bool kDegradedByDamage = false;
  static constexpr bool kClosedFormKirchhoff = false;
  static constexpr int kCodimension = 1;  // a curve element

  // normal_stiffness = E, shear_stiffness = mu of (E, nu), friction 0.3 until the scene sets
  // them.
  static void map_parameters(MaterialParams* m, Real fiber_scale1, Real fiber_scale2);

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);

  // The frictional return map (supplement §3, §5): with the cross-section compressed
  // (0 < J < 1, pressure p < 0), the shear of the normals is limited by Coulomb's
  // gamma |Rh r| <= -c_F p and scaled onto it; apart (J >= 1) there is no shear (r = 0) and the
  // cross-section is reset to its rest shape (Rh = I: the next contact starts from rest); an
  // inverted cross-section (J <= 0) keeps no shear either. F becomes Q R. Returns the state.
  template <int Dim>
  static ContactState return_map(const MaterialParams& m, Mat<Dim>* F);
};

}  // namespace tear
