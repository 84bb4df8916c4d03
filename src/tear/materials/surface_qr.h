// materials/: the QR-based elastoplastic surface of Jiang et al. 2017 (supplement §4): cloth, a
// triangle element in 3D whose F = [d1 d2 d3] D^-1 has the mesh's edges as tangent columns and
// the grid-advected normal d3 as the third. Energy, stress, dP and the frictional return map.
// Knows nothing of particles.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// With F = Q R, R = [[Rh, r], [0, r33]] (Rh the 2x2 in-plane block, r = (r13, r23)):
//   Psi = h(Rh) + gamma/2 |r|^2 + f(r33),  f(x) = k/3 (1 - x)^3 (x < 1), 0 otherwise,
//   h(Rh) = mu |Rh - rot(Rh)|^2 + lambda/2 (det Rh - 1)^2            (fixed corotated, 2x2)
//         + kx/2 (r11 - 1)^2 + ky/2 (|(r12, r22)| - 1)^2              (warp and weft)
// mu, lambda are the plane-stress Lame parameters of (E, nu) (a thin sheet: lambda =
// E nu / (1 - nu^2)); k = normal_stiffness, gamma = shear_stiffness, kx, ky = fiber scales * mu
// along the element's first rest axis (the warp) and its in-plane normal (the weft).
// In the Q basis the stress is (supplement §4 with A R^-T expanded, no division by r33):
//   Q^T P = [[dh/dRh, gamma r], [(gamma r33 - f') (Rh^-1 r)^T, f']].
// Dim 3 only: the 2D instantiation exists for the registry's dispatch and must not be called
// (the scene refuses surfaces in 2D).
struct SurfaceQr {
  static constexpr Model kModel = Model::SurfaceQr;
  static constexpr const char* kName = "surface_qr";
  static constexpr bool kHasFiberStiffness = true;  // warp and weft: kx, ky
  static constexpr bool kDegradedByDamage = false;
  static constexpr bool kClosedFormKirchhoff = false;
  static constexpr int kCodimension = 2;  // a surface element

  // Plane-stress lambda; kx, ky = fiber scales * mu; normal_stiffness = E, shear_stiffness = mu,
  // friction 0.3 until the scene sets them.
  static void map_parameters(MaterialParams* m, Real fiber_scale1, Real fiber_scale2);

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);

  // The frictional return map (supplement §4.1): layers in contact (0 <= r33 < 1) resist
  // shear up to Coulomb's limit, gamma |r| <= c_F k (1 - r33)^2, so r is scaled onto it; layers
  // apart (r33 >= 1) carry no shear (r = 0) and r33 is reset to 1, so that a layer meets the
  // next one at its rest thickness (as libWetCloth does; the supplement leaves r33 alone);
  // inverted (r33 < 0), r = 0. F becomes Q R with the new R. Returns the contact state.
  template <int Dim>
  static ContactState return_map(const MaterialParams& m, Mat<Dim>* F);
};

}  // namespace tear
