// damage/: the anisotropic crack driving force of AnisoMPM (paper §3, EQUATIONS.md §1) and
// the degradation function. Pure functions of F, the fiber frame and the damage parameters;
// the phase-field solvers over particles and grid are in damage/phase_field.h.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// g(d) = (1 - d)^2 (1 - r) + r: g(0) = 1, g(1) = r (EQUATIONS.md §2 "Degradation").
inline Real degradation(Real d, Real residual) {
  return (1 - d) * (1 - d) * (1 - residual) + residual;
}

// Tensile part sigma+ = sum_a <sigma_a> n_a n_a^T of a symmetric matrix (closed form, no
// eigenvectors). Error ~eps |sym| in general; in 3D with two eigenvalues near 0 it grows
// towards ~sqrt(eps) |sym|, as for any solution through the characteristic cubic.
template <int Dim>
Mat<Dim> tensile_part(const Mat<Dim>& sym);

// World-space structural tensor A = I + alpha1 (R a1)(R a1)^T + alpha2 (R a2)(R a2)^T, with
// R the rotation of the polar decomposition of F and D = [a1 a2 (a3)] the rest fiber frame.
template <int Dim>
Mat<Dim> structural_tensor(const Mat<Dim>& F, const Mat<Dim>& D, const Real alpha[2]);

// The crack surface term's tensor M = I + sum_k beta_k w_k w_k^T (DamageParams::surface), with
// w_k = F a_k / |F a_k| the deformed fiber k of the rest frame D = [a1 a2 (a3)]. A fiber
// crushed to zero length (|F a_k| = 0) adds nothing.
template <int Dim>
Mat<Dim> crack_surface_tensor(const Mat<Dim>& F, const Mat<Dim>& D, const double beta[2]);

// Phi = (A sigma+) : (sigma+ A) / sigma_c^2 for a given Cauchy stress and structural tensor.
template <int Dim>
Real driving_phi(const Mat<Dim>& cauchy, const Mat<Dim>& A, Real sigma_c);

// Phi of a particle: Cauchy stress sigma = P F^T / J of the undegraded model. An inverted or
// collapsed particle (J <= 0) is in compression and has no tensile driving force: 0.
template <int Dim>
Real particle_phi(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                  const Real alpha[2], Real sigma_c);

// max(Phi - 1, 0), the particle's drive before the slope zeta, from its undegraded first Piola
// stress P and J = det F (the constitutive phase's): the value particle_phi gives, but
// skipping the tensile part and the rotation when a bound shows Phi <= 1.
template <int Dim>
Real phi_excess(const Mat<Dim>& P, Real J, const Mat<Dim>& F, const Mat<Dim>& D,
                const Real alpha[2], Real sigma_c);

// Where cracking starts, for choosing sigma_c: the stretch 1 + e of the uniaxial strain
// F = I + e n n^T (the other directions held) at which a particle with rest fiber frame D
// first reaches Phi = 1, found by scanning e up to `max_stretch` - 1 and bisecting. Infinity
// when Phi stays below 1 up to `max_stretch` (e.g. along fibers with alpha = -1).
template <int Dim>
Real crack_onset_stretch(const MaterialParams& m, const Mat<Dim>& D, const Real alpha[2],
                         Real sigma_c, const Vec<Dim>& n, Real max_stretch = 4);

}  // namespace tear
