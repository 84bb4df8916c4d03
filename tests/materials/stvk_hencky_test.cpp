#include "tear/materials/stvk_hencky.h"

#include "material_test_util.h"

namespace tear {
namespace {

using namespace material_test;

TEST(StvkHencky, StressIsGradientOfEnergy) {
  expect_stress_is_energy_gradient<2>(Model::StvkHencky, 1);
  expect_stress_is_energy_gradient<3>(Model::StvkHencky, 1);
}

// The numerical fallback (helpers.h) must be a linear map of dF, whatever its scale.
TEST(StvkHencky, FallbackDifferentialIsLinearInDF) {
  expect_differential_is_linear<2>(Model::StvkHencky, 1);
  expect_differential_is_linear<3>(Model::StvkHencky, 1);
}

TEST(StvkHencky, FallbackDifferentialAgreesWithStressDifferencesAtSecondOrder) {
  expect_differential_agrees_at_second_order<2>(Model::StvkHencky, 1);
  expect_differential_agrees_at_second_order<3>(Model::StvkHencky, 1);
}

// Far from identity too (large, near-singular and inverted F), at the FD tolerance.
TEST(StvkHencky, FallbackDifferentialMatchesFiniteDifferencesOfStress) {
  expect_differential_matches_stress_differences<2>(Model::StvkHencky, 1);
  expect_differential_matches_stress_differences<3>(Model::StvkHencky, 1);
}

// Uniaxial stretch F = diag(s, 1, 1): P_11 = (2 mu + lambda) log(s) / s, P_22 = lambda log(s).
TEST(StvkHencky, UniaxialStretchMatchesClosedForm) {
  const MaterialParams m = make_material(Model::StvkHencky, 1000, 0.3, 1);
  for (double s : {0.5, 0.9, 1.3, 2.0}) {
    Mat<3> F = Mat<3>::Identity();
    F(0, 0) = s;
    const Mat<3> P = first_piola<3>(m, F, Mat<3>::Identity());
    EXPECT_NEAR(P(0, 0), (2 * m.mu + m.lambda) * std::log(s) / s, 1e-10 * m.E) << s;
    EXPECT_NEAR(P(1, 1), m.lambda * std::log(s), 1e-10 * m.E) << s;
  }
}

}  // namespace
}  // namespace tear
