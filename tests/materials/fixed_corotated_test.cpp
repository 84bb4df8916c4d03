#include "tear/materials/fixed_corotated.h"

#include "material_test_util.h"
#include "tear/math/polar.h"

namespace tear {
namespace {

using namespace material_test;

TEST(FixedCorotated, StressIsGradientOfEnergy) {
  expect_stress_is_energy_gradient<2>(Model::FixedCorotated, 1);
  expect_stress_is_energy_gradient<3>(Model::FixedCorotated, 1);
}

TEST(FixedCorotated, StressDifferentialMatchesFiniteDifferencesOfStress) {
  expect_differential_matches_stress_differences<2>(Model::FixedCorotated, 1);
  expect_differential_matches_stress_differences<3>(Model::FixedCorotated, 1);
}

TEST(FixedCorotated, StressDifferentialIsLinearInDF) {
  expect_differential_is_linear<2>(Model::FixedCorotated, 1);
  expect_differential_is_linear<3>(Model::FixedCorotated, 1);
}

// dR of the polar decomposition against central differences of polar_rotation(), for mild,
// large, near-singular and inverted F; R^T dR must be skew (R stays a rotation).
template <int Dim>
void expect_polar_rotation_differential_matches() {
  std::mt19937_64 rng(31 + Dim);
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> dF = random_direction<Dim>(rng);
    const Mat<Dim> R = polar_rotation<Dim>(F);
    const Mat<Dim> dR = polar_rotation_differential<Dim>(F, R, dF);
    const double h = 1e-6;
    const Mat<Dim> fd =
        (polar_rotation<Dim>(F + h * dF) - polar_rotation<Dim>(F - h * dF)) / (2 * h);
    EXPECT_LT((dR - fd).norm(), 1e-6 * (1 + dR.norm())) << "Dim " << Dim << "\nF =\n" << F;
    const Mat<Dim> W = R.transpose() * dR;
    EXPECT_LT((W + W.transpose()).norm(), 1e-12 * (1 + W.norm()));
  }
}

TEST(FixedCorotated, PolarRotationDifferentialMatchesFiniteDifferences) {
  expect_polar_rotation_differential_matches<2>();
  expect_polar_rotation_differential_matches<3>();
}

TEST(FixedCorotated, ParametersAreTheLameParametersWithoutFibers) {
  const MaterialParams c = make_material(Model::FixedCorotated, 1000, 0.25, 2, 4, 1);
  const double mu = 400, lambda = 400;
  EXPECT_DOUBLE_EQ(c.mu, mu);
  EXPECT_DOUBLE_EQ(c.lambda, lambda);
  EXPECT_DOUBLE_EQ(c.kx, 0);
  EXPECT_DOUBLE_EQ(c.ky, 0);
  EXPECT_DOUBLE_EQ(wave_speed(c), std::sqrt((lambda + 2 * mu) / 2));
}

}  // namespace
}  // namespace tear
