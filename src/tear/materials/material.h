// materials/: constitutive models as pure functions of F and the rest fiber frame D, one file
// each. Owns energy, stress P, its differential dP and parameter mapping; knows no grid.
#pragma once

#include <string>

#include "tear/math/types.h"

namespace tear {

// One value per model in registry.h's `Models` list, in the same order (checked there). Each
// model is one file (qr_aniso.h, fixed_corotated.h, neo_hookean.h, stvk_hencky.h; the
// codimensional surface_qr.h and curve_qr.h).
enum class Model { QrAniso, FixedCorotated, NeoHookean, StvkHencky, SurfaceQr, CurveQr };

// What a codimensional model's return map found (surface_qr.h, curve_qr.h): layers apart (no
// contact: no shear, the normal reset), in contact within the friction limit (stick), on it
// (slip: the shear was scaled down), or inverted (passed through each other). A frame column.
enum class ContactState : uint8_t { Apart = 0, Stick = 1, Slip = 2, Inverted = 3 };

// The friction coefficient c_F of a codimensional material whose scene gives none (a typical
// cloth-on-cloth or hair-on-hair value).
constexpr Real kDefaultCodimFriction = Real(0.3);

// Parameters of one material, already mapped from the user's (E, nu, fiber_scale).
// `mu`, `lambda` are the values the model's formula uses:
//  - fixed_corotated, neo_hookean, stvk_hencky: the Lame parameters of (E, nu).
//  - qr_aniso: lambda = lambda_Lame + mu, so that the small-strain response equals
//    linear elasticity with (E, nu) (EQUATIONS.md §2, "Small-strain note").
//  - surface_qr: mu and the plane-stress lambda = E nu / (1 - nu^2) of the in-plane model.
// kx = fiber_scale[0] * mu, ky = fiber_scale[1] * mu (qr_aniso, and surface_qr's warp and weft;
// 2D uses kx only).
// The codimensional models (Jiang et al. 2017) also use normal_stiffness (k: the contact
// energy of a compressed normal or cross-section), shear_stiffness (gamma: the shear of the
// normals against the element) and friction (c_F, Coulomb's coefficient of their return map).
struct MaterialParams {
  Model model = Model::QrAniso;
  Real E = 1, nu = 0, rho = 1;
  Real mu = 0, lambda = 0;
  Real kx = 0, ky = 0;
  Real normal_stiffness = 0, shear_stiffness = 0, friction = 0;
  // Codimensional models: the modulus of the optional bending energy (codim/bending.h), 0 off.
  Real bending_modulus = 0;
};

// Lame parameters of linear elasticity.
Real lame_mu(Real E, Real nu);
Real lame_lambda(Real E, Real nu);

// The Lame parameters of (E, nu), then the model's own mapping (its `map_parameters`).
MaterialParams make_material(Model model, Real E, Real nu, Real rho, Real fiber_scale1 = 0,
                             Real fiber_scale2 = 0);

// P-wave speed sqrt((lambda_Lame + 2 mu + max(kx, ky)) / rho): the elastic time-step limit. For
// the codimensional models the stiffest of their moduli: the in-plane (surface: E / (1 - nu^2))
// or stretch (curve: E) one with the fiber terms, the shear and twice the normal stiffness (the
// contact energy's curvature at full compression).
Real wave_speed(const MaterialParams& m);

// The manifold dimension of a model's elements: 0 volumetric, 1 curve, 2 surface (registry.h).
int model_codimension(Model m);

// The registered name ("qr_aniso", ...), "?" for a value outside the enum.
const char* model_name(Model m);
bool parse_model(const std::string& name, Model* out);

// Energy density Psi(F) per unit rest volume. `D` is the orthonormal rest fiber frame
// [a1 a2 (a3)] (columns); isotropic models ignore it. `g` is the damage degradation
// factor g(d) (EQUATIONS.md §2 "Degradation"); only qr_aniso uses it, 1 = undamaged.
template <int Dim>
Real energy_density(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g = 1);

// First Piola-Kirchhoff stress P = dPsi/dF with the same arguments.
template <int Dim>
Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g = 1);

// Kirchhoff stress tau = P F^T with the same arguments: what MLS-MPM's P2G spreads (its
// affine momentum term is -dt V0 D^-1 tau). Closed form where the model's traits say so
// (registry.h, kClosedFormKirchhoff: cheaper than forming P), else first_piola times F^T.
template <int Dim>
Mat<Dim> kirchhoff_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                          Real g = 1);

// Stress differential dP = dP/dF : dF (the directional derivative of first_piola along dF,
// at fixed D and g), for implicit integration. Every model writes it in closed form; it is
// checked against central differences of P (tests/materials/).
template <int Dim>
Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                             const Mat<Dim>& dF, Real g = 1);

// A codimensional model's frictional return map on an element's F (surface_qr.h, curve_qr.h);
// returns what it found. Must not be called for a volumetric model.
template <int Dim>
ContactState codim_return_map(const MaterialParams& m, Mat<Dim>* F);

// dP/dF as a Dim^2 x Dim^2 matrix on column-major vec(F) (vec(dP) = A vec(dF)): the Hessian of
// Psi, symmetric up to round-off. Built column by column from stress_differential.
template <int Dim>
using StressDerivative = Eigen::Matrix<Real, Dim * Dim, Dim * Dim>;

template <int Dim>
StressDerivative<Dim> stress_derivative(const MaterialParams& m, const Mat<Dim>& F,
                                        const Mat<Dim>& D, Real g = 1);

// The nearest positive semi-definite matrix to stress_derivative (symmetrised, its negative
// eigenvalues set to zero): what a Newton step on the incremental potential uses, so that the
// system it solves stays positive definite where the energy is not convex (compression, inverted
// or squashed fibers). Per-particle eigen-decomposition of the Dim^2 x Dim^2 matrix: exact for
// every model, including qr_aniso, whose fiber terms have no closed-form eigensystem in F.
template <int Dim>
StressDerivative<Dim> projected_stress_derivative(const MaterialParams& m, const Mat<Dim>& F,
                                                  const Mat<Dim>& D, Real g = 1);

// qr_aniso: first_piola(m, F, D, g) from the undegraded first_piola(m, F, D) = P, without the
// QR: g changes only mu and lambda, and the terms they multiply are, for an orthonormal
// right-handed D and det F > 0 (Q cof R D^T = cof(F D) D^T = cof F),
//   P_g = P + (g - 1) mu (F - cof F) + [J >= 1] (g - 1) lambda (J - 1) cof F.
// Defined in qr_aniso.cpp.
template <int Dim>
Mat<Dim> degrade_qr_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& P, Real g);

}  // namespace tear
