#include "tear/materials/neo_hookean.h"

#include "material_test_util.h"

namespace tear {
namespace {

using namespace material_test;

TEST(NeoHookean, StressIsGradientOfEnergy) {
  expect_stress_is_energy_gradient<2>(Model::NeoHookean, 1);
  expect_stress_is_energy_gradient<3>(Model::NeoHookean, 1);
}

// Includes collapsed and inverted F, where J is below the log floor (helpers.h).
TEST(NeoHookean, StressDifferentialMatchesFiniteDifferencesOfStress) {
  expect_differential_matches_stress_differences<2>(Model::NeoHookean, 1);
  expect_differential_matches_stress_differences<3>(Model::NeoHookean, 1);
}

TEST(NeoHookean, StressDifferentialIsLinearInDF) {
  expect_differential_is_linear<2>(Model::NeoHookean, 1);
  expect_differential_is_linear<3>(Model::NeoHookean, 1);
}

// Uniaxial stretch F = diag(s, 1, 1), cof F = diag(1, s, s): in closed form
// P_11 = mu s + (lambda log s - mu) / s, P_22 = lambda log s, and along dF = e1 e1^T
// dP_11 = mu + (lambda (1 - log s) + mu) / s^2, dP_22 = lambda / s.
TEST(NeoHookean, UniaxialStretchMatchesClosedForm) {
  const MaterialParams m = make_material(Model::NeoHookean, 1000, 0.3, 1);
  for (double s : {0.5, 0.9, 1.0, 1.3, 2.0}) {
    Mat<3> F = Mat<3>::Identity();
    F(0, 0) = s;
    const double P11 = m.mu * s + (m.lambda * std::log(s) - m.mu) / s;
    EXPECT_NEAR(first_piola<3>(m, F, Mat<3>::Identity())(0, 0), P11, 1e-10 * m.E) << s;
    Mat<3> dF = Mat<3>::Zero();
    dF(0, 0) = 1;
    const double dP11 = m.mu + (m.lambda * (1 - std::log(s)) + m.mu) / (s * s);
    const Mat<3> dP = stress_differential<3>(m, F, Mat<3>::Identity(), dF);
    EXPECT_NEAR(dP(0, 0), dP11, 1e-10 * m.E) << s;
    EXPECT_NEAR(dP(1, 1), m.lambda / s, 1e-10 * m.E) << s;
    EXPECT_NEAR(first_piola<3>(m, F, Mat<3>::Identity())(1, 1), m.lambda * std::log(s), 1e-10 * m.E)
        << s;
  }
}

}  // namespace
}  // namespace tear
