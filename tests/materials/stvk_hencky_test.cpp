#include "tear/materials/stvk_hencky.h"

#include "material_test_util.h"

namespace tear {
namespace {

using namespace material_test;

TEST(StvkHencky, StressIsGradientOfEnergy) {
  expect_stress_is_energy_gradient<2>(Model::StvkHencky, 1);
  expect_stress_is_energy_gradient<3>(Model::StvkHencky, 1);
}

// The analytic differential (through the SVD) is a linear map of dF, whatever its scale.
TEST(StvkHencky, DifferentialIsLinearInDF) {
  expect_differential_is_linear<2>(Model::StvkHencky, 1);
  expect_differential_is_linear<3>(Model::StvkHencky, 1);
}

TEST(StvkHencky, DifferentialAgreesWithStressDifferencesAtSecondOrder) {
  expect_differential_agrees_at_second_order<2>(Model::StvkHencky, 1);
  expect_differential_agrees_at_second_order<3>(Model::StvkHencky, 1);
}

// Far from identity too (large, near-singular and inverted F), at the FD tolerance.
TEST(StvkHencky, DifferentialMatchesFiniteDifferencesOfStress) {
  expect_differential_matches_stress_differences<2>(Model::StvkHencky, 1);
  expect_differential_matches_stress_differences<3>(Model::StvkHencky, 1);
}

// Equal and nearly equal singular values (where the SVD's rotated-frame formula divides by
// sigma_i - sigma_j and takes its limit instead), and the log floor (sigma below 1e-2).
TEST(StvkHencky, DifferentialAtRepeatedSingularValuesAndBelowTheLogFloor) {
  std::mt19937_64 rng(31);
  const MaterialParams m = make_material(Model::StvkHencky, 1000, 0.3, 1);
  const std::vector<Vec<3>> cases = {Vec<3>(1.2, 1.2, 0.7), Vec<3>(1.2, 1.2 + 1e-9, 0.7),
                                     Vec<3>(1.1, 1.1, 1.1), Vec<3>(0.9, 0.9, -0.3),
                                     Vec<3>(1.0, 0.6, 5e-3), Vec<3>(1.3, 0.8, -4e-3)};
  for (const Vec<3>& s : cases)
    for (int k = 0; k < 3; ++k) {
      const Mat<3> F = with_singular_values<3>(rng, s), dF = random_direction<3>(rng);
      const Mat<3> dP = stress_differential<3>(m, F, Mat<3>::Identity(), dF);
      const double h = 1e-7;
      const Mat<3> fd = (first_piola<3>(m, F + h * dF, Mat<3>::Identity()) -
                         first_piola<3>(m, F - h * dF, Mat<3>::Identity())) /
                        (2 * h);
      EXPECT_LT((dP - fd).norm(), 1e-5 * (1 + dP.norm())) << s.transpose();
    }
  const Mat<2> F2 = with_singular_values<2>(rng, Vec<2>(0.8, 0.8)), dF2 = random_direction<2>(rng);
  const Mat<2> fd2 = (first_piola<2>(m, F2 + 1e-7 * dF2, Mat<2>::Identity()) -
                      first_piola<2>(m, F2 - 1e-7 * dF2, Mat<2>::Identity())) /
                     2e-7;
  EXPECT_LT((stress_differential<2>(m, F2, Mat<2>::Identity(), dF2) - fd2).norm(),
            1e-5 * (1 + fd2.norm()));
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
