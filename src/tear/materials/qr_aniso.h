// materials/: the QR-based anisotropic model of AnisoMPM (paper §5; EQUATIONS.md §2): energy,
// stress P, dP, parameter mapping and the damage-degraded stress. Knows nothing of particles.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// With F D = Q R (Givens QR, EQUATIONS.md §2 sign convention):
//   Psi = mu/2 (|R|^2 - d) - mu (J - 1) + lambda/2 (J - 1)^2
//       + kx/2 (r11 - 1)^2 + ky/2 (sqrt(r12^2 + r22^2) - 1)^2        (ky term 3D only)
// degraded by g = g(d) on the mu terms always and on the lambda term in tension (J >= 1);
// fiber terms are never degraded (paper §3.3, §5.2; supplement §3.6).
struct QrAniso {
  static constexpr Model kModel = Model::QrAniso;
  static constexpr const char* kName = "qr_aniso";
  static constexpr bool kHasFiberStiffness = true;  // uses kx (and ky in 3D)
  static constexpr bool kDegradedByDamage = true;   // uses g
  static constexpr int kCodimension = 0;
  static constexpr bool kClosedFormKirchhoff = false;

  // lambda = lambda_Lame + mu (EQUATIONS.md §2 small-strain note); kx, ky = fiber scales * mu.
  static void map_parameters(MaterialParams* m, Real fiber_scale1, Real fiber_scale2);

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);

  // Division-free closed form of supplement §3.5: finite as r11 -> 0.
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);

  // Analytic, from the QR-free form of the same energy (qr_aniso.cpp); degraded like P.
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);
};

}  // namespace tear
