// Properties every registered model must have, and the shared helpers of helpers.h.
#include <Eigen/Eigenvalues>

#include "material_test_util.h"
#include "tear/materials/helpers.h"
#include "tear/materials/registry.h"

namespace tear {
namespace {

using namespace material_test;

// Every volumetric model in the registry: a model added there is held to these properties
// without edits. The codimensional ones (surface_qr, curve_qr) have properties of their own
// (codim_model_test.cpp): no linear elasticity of (E, nu) in every direction.
std::vector<Model> registered_models() {
  std::vector<Model> models;
  for (const ModelTraits& t : kModelTraits)
    if (t.codimension == 0) models.push_back(t.model);
  return models;
}

template <int Dim>
void expect_rest_and_rotation_are_stress_free() {
  std::mt19937_64 rng(5);
  for (Model model : registered_models()) {
    const MaterialParams m = make_material(model, 1000, 0.3, 1, 10, 5);
    for (int k = 0; k < 10; ++k) {
      const Mat<Dim> D = random_rotation<Dim>(rng);
      const Mat<Dim> R = random_rotation<Dim>(rng);
      EXPECT_LT(first_piola<Dim>(m, Mat<Dim>::Identity(), D).norm(), 1e-12 * m.E)
          << model_name(model);
      EXPECT_NEAR(energy_density<Dim>(m, Mat<Dim>::Identity(), D), 0, 1e-12);
      EXPECT_LT(first_piola<Dim>(m, R, D).norm(), 1e-12 * m.E) << model_name(model);
      EXPECT_NEAR(energy_density<Dim>(m, R, D), 0, 1e-10);
    }
  }
}

TEST(Materials, ZeroStressAtRestAndUnderRotation) {
  expect_rest_and_rotation_are_stress_free<2>();
  expect_rest_and_rotation_are_stress_free<3>();
}

template <int Dim>
void expect_rotation_invariance() {
  std::mt19937_64 rng(9);
  for (Model model : registered_models()) {
    const MaterialParams m = make_material(model, 1000, 0.3, 1, 10, 5);
    for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
      const Mat<Dim> D = random_rotation<Dim>(rng);
      const Mat<Dim> R = random_rotation<Dim>(rng);
      const Mat<Dim> P = first_piola<Dim>(m, F, D);
      EXPECT_LT((first_piola<Dim>(m, R * F, D) - R * P).norm(), 1e-9 * (1 + P.norm()))
          << model_name(model);
      EXPECT_NEAR(energy_density<Dim>(m, R * F, D), energy_density<Dim>(m, F, D),
                  1e-9 * (1 + std::abs(energy_density<Dim>(m, F, D))));
    }
  }
}

TEST(Materials, RotationInvariance) {
  expect_rotation_invariance<2>();
  expect_rotation_invariance<3>();
}

// kirchhoff_stress is P F^T for every model, closed form or not, over near-identity, large,
// near-singular and inverted F (where the floored log's slope enters the closed form).
template <int Dim>
void expect_kirchhoff_is_p_times_f_transpose() {
  std::mt19937_64 rng(21);
  for (Model model : registered_models()) {
    const MaterialParams m = make_material(model, 1000, 0.3, 1, 10, 5);
    for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
      const Mat<Dim> D = random_rotation<Dim>(rng);
      for (Real g : {Real(1), Real(0.3)}) {
        const Mat<Dim> tau = first_piola<Dim>(m, F, D, g) * F.transpose();
        EXPECT_LT((kirchhoff_stress<Dim>(m, F, D, g) - tau).norm(), 1e-10 * (m.E + tau.norm()))
            << model_name(model) << " Dim " << Dim << " g " << g << "\nF\n" << F;
      }
    }
  }
}

TEST(Materials, KirchhoffStressIsPTimesFTranspose) {
  expect_kirchhoff_is_p_times_f_transpose<2>();
  expect_kirchhoff_is_p_times_f_transpose<3>();
}

template <int Dim>
void expect_small_strain_matches_linear_elasticity(Model model) {
  const double E = 2500, nu = 0.27;
  const MaterialParams m = make_material(model, E, nu, 1);
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  std::mt19937_64 rng(17);
  const double eps = 1e-6;
  for (int k = 0; k < 5; ++k) {
    const Mat<Dim> H = random_matrix<Dim>(rng, 1);
    const Mat<Dim> strain = eps * (H + H.transpose()) / 2;
    const Mat<Dim> sigma = 2 * mu * strain + lambda * strain.trace() * Mat<Dim>::Identity();
    const Mat<Dim> P =
        first_piola<Dim>(m, Mat<Dim>::Identity() + eps * H, random_rotation<Dim>(rng));
    EXPECT_LT((P - sigma).norm(), 1e-4 * sigma.norm()) << model_name(model) << " Dim " << Dim;
  }
}

TEST(Materials, SmallStrainMatchesLinearElasticityWithEAndNu) {
  for (Model model : registered_models()) {
    expect_small_strain_matches_linear_elasticity<2>(model);
    expect_small_strain_matches_linear_elasticity<3>(model);
  }
}

// At rest, dP is the elasticity tensor of linear elasticity with (E, nu): dP = 2 mu sym(dF) +
// lambda_Lame tr(dF) I, for every model and fiber frame (no fiber stiffness here).
template <int Dim>
void expect_rest_differential_is_linear_elasticity(Model model) {
  const double E = 2500, nu = 0.27;
  const MaterialParams m = make_material(model, E, nu, 1);
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  std::mt19937_64 rng(29);
  for (int k = 0; k < 5; ++k) {
    const Mat<Dim> dF = random_direction<Dim>(rng), D = random_rotation<Dim>(rng);
    const Mat<Dim> expected =
        mu * (dF + dF.transpose()) + lambda * dF.trace() * Mat<Dim>::Identity();
    const Mat<Dim> dP = stress_differential<Dim>(m, Mat<Dim>::Identity(), D, dF);
    EXPECT_LT((dP - expected).norm(), 1e-7 * expected.norm())
        << model_name(model) << " Dim " << Dim;
  }
}

TEST(Materials, StressDifferentialAtRestIsTheLinearElasticityTensor) {
  for (Model model : registered_models()) {
    expect_rest_differential_is_linear_elasticity<2>(model);
    expect_rest_differential_is_linear_elasticity<3>(model);
  }
}

// Entrywise central differences of P (numeric_stress_differential) reproduce every model's
// analytic differential: to ~1e-9 relative near identity (|F - I| ~ 0.3), and to the h^2
// truncation far from it (large stretches, J near 0, inversion). With damage (g = 0.3) too.
template <int Dim>
void expect_numeric_differential_matches_analytic(Model model, Real g) {
  std::mt19937_64 rng(37 + Dim);
  const MaterialParams m = test_material(model);
  const std::vector<Mat<Dim>> Fs = test_deformations<Dim>(rng);
  for (size_t k = 0; k < Fs.size(); ++k) {
    const Mat<Dim>& F = Fs[k];
    const bool near_identity = k < 12 && k % 2 == 0;
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    const auto stress = [&](const Mat<Dim>& G) { return first_piola<Dim>(m, G, D, g); };
    const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF, g);
    const Mat<Dim> numeric = numeric_stress_differential<Dim>(stress, F, dF);
    EXPECT_LT((numeric - dP).norm(), (near_identity ? 1e-9 : 1e-6) * (1 + dP.norm()))
        << model_name(model) << " Dim " << Dim << "\nF =\n"
        << F;
  }
}

TEST(Materials, EntrywiseStressDifferencesMatchTheAnalyticDifferential) {
  for (Model model : registered_models())
    for (Real g : {1.0, 0.3}) {
      expect_numeric_differential_matches_analytic<2>(model, g);
      expect_numeric_differential_matches_analytic<3>(model, g);
    }
}

// stress_derivative is the Hessian of Psi: its columns are dP along the unit matrices, and it is
// symmetric. Its projection is symmetric positive semi-definite, equals the Hessian where that
// is already PSD, and only adds: projected - Hessian is PSD (it removes the negative part).
template <int Dim>
void expect_projected_derivative_is_psd(Model model, Real g) {
  using A = StressDerivative<Dim>;
  std::mt19937_64 rng(53 + Dim);
  const MaterialParams m = test_material(model);
  int indefinite = 0;
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    const A H = stress_derivative<Dim>(m, F, D, g);
    const A P = projected_stress_derivative<Dim>(m, F, D, g);
    const A sym = (H + H.transpose()) / 2;
    const Real scale = 1 + H.norm();
    EXPECT_LT((H * dF.reshaped() - stress_differential<Dim>(m, F, D, dF, g).reshaped()).norm(),
              1e-12 * scale);
    EXPECT_LT((H - H.transpose()).norm(), 1e-9 * scale) << model_name(model) << "\nF =\n" << F;
    EXPECT_LT((P - P.transpose()).norm(), 1e-12 * scale);
    Eigen::SelfAdjointEigenSolver<A> eh(sym), ep(P), added(P - sym);
    EXPECT_GE(ep.eigenvalues().minCoeff(), -1e-10 * scale) << model_name(model);
    EXPECT_GE(added.eigenvalues().minCoeff(), -1e-10 * scale) << model_name(model);
    if (eh.eigenvalues().minCoeff() >= 0) {
      EXPECT_LT((P - H).norm(), 1e-9 * scale);
    } else {
      ++indefinite;
      // The projection keeps the positive part: same action on the top eigenvector.
      const int top = Dim * Dim - 1;
      const auto v = eh.eigenvectors().col(top);
      EXPECT_NEAR(v.dot(P * v), eh.eigenvalues()[top], 1e-9 * scale);
    }
  }
  // The test deformations include compressed and inverted ones, where no model is convex.
  EXPECT_GT(indefinite, 0) << model_name(model) << " Dim " << Dim;
}

TEST(Materials, ProjectedStressDerivativeIsPositiveSemiDefinite) {
  for (Model model : registered_models())
    for (Real g : {1.0, 0.3}) {
      expect_projected_derivative_is_psd<2>(model, g);
      expect_projected_derivative_is_psd<3>(model, g);
    }
}

// At rest without fiber stiffness every model's Hessian is the (positive definite) elasticity
// tensor: the projection changes nothing.
TEST(Materials, ProjectionLeavesTheRestTensorAlone) {
  std::mt19937_64 rng(61);
  for (Model model : registered_models()) {
    const MaterialParams m = make_material(model, 1000, 0.3, 1);
    const Mat<3> D = random_rotation<3>(rng);
    const StressDerivative<3> H = stress_derivative<3>(m, Mat<3>::Identity(), D);
    const StressDerivative<3> P = projected_stress_derivative<3>(m, Mat<3>::Identity(), D);
    EXPECT_LT((P - H).norm(), 1e-9 * H.norm()) << model_name(model);
  }
}

// The floored log is C2: slope and curvature are its derivatives on both sides of the floor,
// and all three are continuous across it.
TEST(SafeLog, SlopeAndCurvatureAreItsDerivativesAcrossTheFloor) {
  const double h = 1e-7;
  for (double x : {-0.5, 0.0, 0.005, 0.0099, 0.0101, 0.05, 1.0, 3.0}) {
    EXPECT_NEAR((safe_log(x + h) - safe_log(x - h)) / (2 * h), safe_log_slope(x),
                1e-6 * std::abs(safe_log_slope(x)))
        << x;
    EXPECT_NEAR((safe_log_slope(x + h) - safe_log_slope(x - h)) / (2 * h), safe_log_curvature(x),
                1e-5 * std::abs(safe_log_curvature(x)))
        << x;
  }
  EXPECT_DOUBLE_EQ(safe_log(1.0), 0);
  const double below = kLogFloor * (1 - 1e-12), above = kLogFloor * (1 + 1e-12);
  EXPECT_NEAR(safe_log(below), safe_log(above), 1e-9);
  EXPECT_NEAR(safe_log_slope(below), safe_log_slope(above), 1e-9 / kLogFloor);
  EXPECT_NEAR(safe_log_curvature(below), safe_log_curvature(above), 1e-9 / (kLogFloor * kLogFloor));
}

// cof F is quadratic in F (linear in 2D), so central differences are exact up to round-off.
template <int Dim>
void expect_cofactor_differential_matches() {
  std::mt19937_64 rng(41 + Dim);
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> dF = random_direction<Dim>(rng);
    const double h = 1e-3;
    const Mat<Dim> fd = (cofactor<Dim>(F + h * dF) - cofactor<Dim>(F - h * dF)) / (2 * h);
    EXPECT_LT((cofactor_differential<Dim>(F, dF) - fd).norm(), 1e-10 * (1 + fd.norm()))
        << "Dim " << Dim;
  }
}

TEST(CofactorDifferential, MatchesFiniteDifferencesOfTheCofactor) {
  expect_cofactor_differential_matches<2>();
  expect_cofactor_differential_matches<3>();
}

}  // namespace
}  // namespace tear
