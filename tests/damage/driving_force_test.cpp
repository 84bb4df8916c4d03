#include "tear/damage/driving_force.h"
#include "tear/math/qr.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace tear {
namespace {

constexpr double kPi = 3.14159265358979323846;

Mat<2> frame2(double degrees) {
  const double t = degrees * kPi / 180;
  Mat<2> D;
  D << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  return D;
}

TEST(Degradation, EndPointsAndMonotone) {
  EXPECT_EQ(degradation(0, 0.01), 1);
  EXPECT_DOUBLE_EQ(degradation(1, 0.01), 0.01);
  double prev = 2;
  for (int k = 0; k <= 10; ++k) {
    const double g = degradation(k / 10.0, 0.05);
    EXPECT_LT(g, prev);
    prev = g;
  }
}

TEST(TensilePart, KeepsOnlyPositiveEigenvalues) {
  Mat<3> s = Mat<3>::Zero();
  s.diagonal() << 2, -1, 0.5;
  const Mat<3> Q = Eigen::AngleAxis<Real>(0.7, Vec<3>(1, 2, 3).normalized()).toRotationMatrix();
  Mat<3> expected = Mat<3>::Zero();
  expected.diagonal() << 2, 0, 0.5;
  EXPECT_LT((tensile_part<3>(Q * s * Q.transpose()) - Q * expected * Q.transpose()).norm(), 1e-12);
  EXPECT_LT(tensile_part<2>(-Mat<2>::Identity()).norm(), 1e-15);
}

// Every sign pattern of eigenvalues (definite ones take a shortcut), against an explicit
// eigen-decomposition.
template <int Dim>
void check_tensile_part_sign_patterns() {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.1, 2);
  for (int pattern = 0; pattern < (1 << Dim); ++pattern)
    for (int k = 0; k < 20; ++k) {
      Vec<Dim> lambda, positive;
      for (int d = 0; d < Dim; ++d) {
        lambda[d] = Real(((pattern >> d) & 1 ? 1 : -1) * u(rng));
        positive[d] = std::max(lambda[d], Real(0));
      }
      Mat<Dim> Q;
      if constexpr (Dim == 2) {
        Q = frame2(360 * u(rng));
      } else {
        Q = Eigen::AngleAxis<Real>(Real(3 * u(rng)), Vec<3>(u(rng), -u(rng), u(rng)).normalized())
                .toRotationMatrix();
      }
      const Mat<Dim> sym = Q * lambda.asDiagonal() * Q.transpose();
      const Mat<Dim> expected = Q * positive.asDiagonal() * Q.transpose();
      EXPECT_LT((tensile_part<Dim>(sym) - expected).norm(), 1e-12) << "pattern " << pattern;
    }
}

TEST(TensilePart, EverySignPatternMatchesTheEigenDecomposition2D) {
  check_tensile_part_sign_patterns<2>();
}
TEST(TensilePart, EverySignPatternMatchesTheEigenDecomposition3D) {
  check_tensile_part_sign_patterns<3>();
}

// Spectra the closed forms find hard, against Eigen's iterative (QL) eigen-decomposition:
// repeated eigenvalues, an eigenvalue at round-off distance from 0, and two eigenvalues
// clustered at 0 around a large one. The last is as hard for any cubic-root method (the old
// computeDirect path included): the pair is resolved only to ~sqrt(eps) |sym|.
template <int Dim>
void check_tensile_part_degenerate_spectra() {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  struct Family {
    const char* name;
    double tolerance;  // on |error| / |sym|
  };
  const Family families[] = {{"generic", 1e-13}, {"double", 1e-13}, {"one_near_zero", 1e-11},
                             {"pair_near_zero", 1e-7}};
  for (int f = 0; f < 4; ++f) {
    double worst = 0;
    for (int k = 0; k < 4000; ++k) {
      Vec<Dim> lambda;
      for (int d = 0; d < Dim; ++d) lambda[d] = Real(u(rng));
      if (f == 1) lambda[1] = lambda[0];
      if (f == 2) lambda[1] = Real(1e-13 * u(rng));
      if (f == 3) {
        lambda[1] = Real(1e-10 * u(rng));
        if (Dim == 3) lambda[2] = Real(1e-10 * u(rng));
      }
      Mat<Dim> Q;
      if constexpr (Dim == 2) {
        Q = frame2(180 * u(rng));
      } else {
        Q = Eigen::AngleAxis<Real>(Real(3 * u(rng)), Vec<3>(u(rng), u(rng), u(rng)).normalized())
                .toRotationMatrix();
      }
      Mat<Dim> sym = Q * lambda.asDiagonal() * Q.transpose();
      sym = (Real(0.5) * (sym + sym.transpose())).eval();
      Eigen::SelfAdjointEigenSolver<Mat<Dim>> eig(sym);  // iterative: accurate eigenvectors
      const Vec<Dim> positive = eig.eigenvalues().cwiseMax(Real(0));
      const Mat<Dim> expected =
          eig.eigenvectors() * positive.asDiagonal() * eig.eigenvectors().transpose();
      worst = std::max(worst, double((tensile_part<Dim>(sym) - expected).norm() / sym.norm()));
    }
    EXPECT_LT(worst, families[f].tolerance) << families[f].name;
  }
}

TEST(TensilePart, DegenerateSpectraMatchAnIterativeDecomposition2D) {
  check_tensile_part_degenerate_spectra<2>();
}
TEST(TensilePart, DegenerateSpectraMatchAnIterativeDecomposition3D) {
  check_tensile_part_degenerate_spectra<3>();
}

// particle_phi evaluates (A s) : (s A) through the fiber vectors without forming A; it must
// equal the same formula through structural_tensor() and driving_phi().
template <int Dim>
void check_particle_phi_matches_the_structural_tensor_form() {
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 3, 1);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const Real alphas[][2] = {{0, 0}, {-1, 0}, {0, -0.7}, {-1, -0.5}, {-0.3, -1}};
  int compared = 0;
  for (int k = 0; k < 200; ++k) {
    Mat<Dim> F = Mat<Dim>::Identity(), B;
    for (int i = 0; i < Dim * Dim; ++i) F.data()[i] += Real(u(rng)), B.data()[i] = Real(u(rng));
    Mat<Dim> D, R;
    qr_decompose<Dim>(Mat<Dim>::Identity() + B, &D, &R);
    const Real J = F.determinant();
    if (J <= 0) continue;
    const Mat<Dim> cauchy = first_piola<Dim>(m, F, D) * F.transpose() / J;
    for (const auto& alpha : alphas) {
      const Real expected = driving_phi<Dim>(cauchy, structural_tensor<Dim>(F, D, alpha), 50);
      EXPECT_NEAR(particle_phi<Dim>(m, F, D, alpha, 50), expected, 1e-12 * (1 + expected));
      ++compared;
    }
  }
  EXPECT_GT(compared, 500);
}

TEST(DrivingForce, ParticlePhiEqualsTheStructuralTensorForm2D) {
  check_particle_phi_matches_the_structural_tensor_form<2>();
}
TEST(DrivingForce, ParticlePhiEqualsTheStructuralTensorForm3D) {
  check_particle_phi_matches_the_structural_tensor_form<3>();
}

// particle_phi_excess returns max(Phi - 1, 0) and skips work when a bound shows Phi <= 1: the
// bound must never hide a positive excess, for any alpha (negative, positive, beyond -1) and
// fiber frames that are not orthonormal.
template <int Dim>
void check_phi_excess_matches_phi() {
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 3, 1);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const Real alphas[][2] = {{0, 0}, {-1, 0}, {-1, -1}, {2, 0.5}, {-1.5, 0}, {-0.3, 4}};
  int below = 0, above = 0;
  for (int k = 0; k < 300; ++k) {
    Mat<Dim> F = Mat<Dim>::Identity(), D = Mat<Dim>::Identity();
    for (int i = 0; i < Dim * Dim; ++i)
      F.data()[i] += Real(u(rng)), D.data()[i] += Real(2 * u(rng));
    if (F.determinant() <= 0 || D.determinant() <= 0) continue;
    for (const auto& alpha : alphas)
      for (Real sigma_c : {5.0, 30.0, 100.0, 400.0}) {
        const Real phi = particle_phi<Dim>(m, F, D, alpha, sigma_c);
        EXPECT_EQ(phi_excess<Dim>(first_piola<Dim>(m, F, D), F.determinant(), F, D, alpha, sigma_c),
                  std::max(phi - 1, Real(0)));
        (phi > 1 ? above : below) += 1;
      }
  }
  EXPECT_GT(below, 500);
  EXPECT_GT(above, 500);
}

TEST(DrivingForce, PhiExcessIsPhiMinusOneOrZero2D) { check_phi_excess_matches_phi<2>(); }
TEST(DrivingForce, PhiExcessIsPhiMinusOneOrZero3D) { check_phi_excess_matches_phi<3>(); }

TEST(DrivingForce, TensionAlongTheFiberDoesNotDriveCracksAcrossItDoes) {
  const Real alpha[2] = {-1, 0};
  const double s = 3, sigma_c = 2;
  const Mat<2> D = frame2(30);
  const Vec<2> a1 = D.col(0), a2 = D.col(1);
  const Mat<2> A = structural_tensor<2>(Mat<2>::Identity(), D, alpha);
  EXPECT_NEAR(driving_phi<2>(s * a1 * a1.transpose(), A, sigma_c), 0, 1e-14);
  EXPECT_NEAR(driving_phi<2>(s * a2 * a2.transpose(), A, sigma_c), (s / sigma_c) * (s / sigma_c),
              1e-12);
  // Compression drives nothing, whatever the fibers.
  EXPECT_NEAR(driving_phi<2>(-s * a2 * a2.transpose(), A, sigma_c), 0, 1e-20);
}

// alpha > 0 (supplement: alpha in [-1, inf)) strengthens the pull along a fiber: tension s
// along a1 gives Phi = ((1 + alpha) s / sigma_c)^2, across it still (s / sigma_c)^2, so such a
// material cracks across its fibers first (crack_onset_stretch agrees).
TEST(DrivingForce, PositiveAlphaStrengthensTensionAlongTheFiber) {
  const double s = 3, sigma_c = 2;
  const Mat<2> D = frame2(-20);
  const Vec<2> a1 = D.col(0), a2 = D.col(1);
  for (Real alpha1 : {0.5, 1.0, 4.0}) {
    const Real alpha[2] = {alpha1, 0};
    const Mat<2> A = structural_tensor<2>(Mat<2>::Identity(), D, alpha);
    EXPECT_NEAR(driving_phi<2>(s * a1 * a1.transpose(), A, sigma_c),
                std::pow((1 + alpha1) * s / sigma_c, 2), 1e-12);
    EXPECT_NEAR(driving_phi<2>(s * a2 * a2.transpose(), A, sigma_c), std::pow(s / sigma_c, 2),
                1e-12);
    const MaterialParams m = make_material(Model::QrAniso, 100, 0.25, 2, 0, 0);
    const Real along = crack_onset_stretch<2>(m, Mat<2>::Identity(), alpha, 10, Vec<2>::UnitX());
    const Real across = crack_onset_stretch<2>(m, Mat<2>::Identity(), alpha, 10, Vec<2>::UnitY());
    EXPECT_LT(along, across) << alpha1;
    const Real none[2] = {0, 0};
    EXPECT_LT(along, crack_onset_stretch<2>(m, Mat<2>::Identity(), none, 10, Vec<2>::UnitX()));
  }
}

// Paper Fig. 11: uniaxial tension s along n, alpha1 = -1, fibers at angle theta to n:
// Phi = (s / sigma_c)^2 sin^4(theta); isotropic: (s / sigma_c)^2 in every direction.
TEST(DrivingForce, FourFiberDirectionsOfFigure11) {
  const double s = 1.5, sigma_c = 1;
  struct Row {
    double fiber_deg;
    Real alpha1;
  };
  for (const Row& row : {Row{0, -1}, Row{45, -1}, Row{90, -1}, Row{0, 0}}) {
    const Real alpha[2] = {row.alpha1, 0};
    const Mat<2> A = structural_tensor<2>(Mat<2>::Identity(), frame2(row.fiber_deg), alpha);
    for (double load_deg : {0.0, 30.0, 45.0, 90.0, 135.0}) {
      const Vec<2> n = frame2(load_deg).col(0);
      const double theta = (load_deg - row.fiber_deg) * kPi / 180;
      const double expected =
          s * s * (row.alpha1 == 0 ? 1.0 : std::pow(std::sin(theta), 4)) / (sigma_c * sigma_c);
      EXPECT_NEAR(driving_phi<2>(s * n * n.transpose(), A, sigma_c), expected, 1e-12)
          << "fiber " << row.fiber_deg << " load " << load_deg;
    }
  }
}

TEST(DrivingForce, RotatingTheBodyRotatesTheStructuralTensor) {
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 5, 2);
  const Real alpha[2] = {-1, -0.5};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 10; ++k) {
    Mat<3> F = Mat<3>::Identity(), B;
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng), B.data()[i] = u(rng);
    Mat<3> D, R;
    qr_decompose<3>(Mat<3>::Identity() + B, &D, &R);
    const Mat<3> Q = Eigen::AngleAxis<Real>(1.1 * k, Vec<3>(1, -2, 0.5).normalized()).toRotationMatrix();
    const Mat<3> A = structural_tensor<3>(F, D, alpha);
    EXPECT_LT((structural_tensor<3>(Q * F, D, alpha) - Q * A * Q.transpose()).norm(), 1e-10);
    const Real phi = particle_phi<3>(m, F, D, alpha, 10);
    EXPECT_NEAR(particle_phi<3>(m, Q * F, D, alpha, 10), phi, 1e-9 * (1 + phi));
  }
}

// The crack surface tensor M = I + sum_k beta_k w_k w_k^T, w_k = F a_k / |F a_k|: eigenvalue
// 1 + beta along the deformed fiber and 1 across it (one fiber), independent of the fiber's
// stretch, turning with the body (M(Q F) = Q M(F) Q^T), and both fibers in 3D; a fiber crushed
// to zero length adds nothing.
template <int Dim>
void check_crack_surface_tensor() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int trial = 0; trial < 20; ++trial) {
    Mat<Dim> F = Mat<Dim>::Identity(), G;
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) F(a, b) += Real(u(rng)), G(a, b) = Real(u(rng));
    const Mat<Dim> Q = Eigen::HouseholderQR<Mat<Dim>>(G).householderQ();  // orthogonal
    Mat<Dim> D = Eigen::HouseholderQR<Mat<Dim>>(F + G).householderQ();
    const double one[2] = {3, 0}, two[2] = {3, 0.5};
    const Mat<Dim> M = crack_surface_tensor<Dim>(F, D, one);
    const Vec<Dim> w = (F * D.col(0)).normalized();
    EXPECT_LT((M - M.transpose()).norm(), 1e-14);
    EXPECT_LT((M * w - 4 * w).norm(), 1e-13);
    Vec<Dim> across = Vec<Dim>::Unit(0) - w * w[0];
    across.normalize();
    EXPECT_LT((M * across - across).norm(), 1e-13);
    EXPECT_LT((crack_surface_tensor<Dim>(Real(2.5) * F, D, one) - M).norm(), 1e-13);
    EXPECT_LT((crack_surface_tensor<Dim>(Q * F, D, one) - Q * M * Q.transpose()).norm(), 1e-13);
    const Vec<Dim> w2 = (F * D.col(1)).normalized();
    const Mat<Dim> M2 = crack_surface_tensor<Dim>(F, D, two);
    EXPECT_LT((M2 - M - Real(0.5) * w2 * w2.transpose()).norm(), 1e-13);
  }
  Mat<Dim> crushed = Mat<Dim>::Identity();
  crushed(0, 0) = 0;
  const double beta[2] = {5, 0};
  EXPECT_EQ(crack_surface_tensor<Dim>(crushed, Mat<Dim>::Identity(), beta), Mat<Dim>::Identity());
}

TEST(CrackSurface, TensorFollowsTheDeformedFibers2D) { check_crack_surface_tensor<2>(); }
TEST(CrackSurface, TensorFollowsTheDeformedFibers3D) { check_crack_surface_tensor<3>(); }

TEST(DrivingForce, ParticleStretchedAcrossItsFibersTearsAlongThemDoesNot) {
  // Uniaxial stretch of a qr_aniso particle; fibers along x, alpha1 = -1.
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.0, 1, 0, 0);
  const Real alpha[2] = {-1, 0};
  const Mat<2> D = Mat<2>::Identity();
  Mat<2> along = Mat<2>::Identity(), across = Mat<2>::Identity();
  along(0, 0) = 1.1;
  across(1, 1) = 1.1;
  // Only the small nonlinear lateral stress of the stretch along the fibers drives damage.
  const Real phi_along = particle_phi<2>(m, along, D, alpha, 10);
  const Real phi_across = particle_phi<2>(m, across, D, alpha, 10);
  EXPECT_GT(phi_across, 50);
  EXPECT_LT(phi_along, 0.01 * phi_across);
  const Real isotropic[2] = {0, 0};
  // Isotropic: the same in both directions; the fibers remove the part along them only.
  const Real iso = particle_phi<2>(m, along, D, isotropic, 10);
  EXPECT_NEAR(particle_phi<2>(m, across, D, isotropic, 10), iso, 1e-9 * iso);
  EXPECT_NEAR(iso, phi_across + phi_along, 1e-9 * iso);
  Mat<2> inverted = Mat<2>::Identity();
  inverted(1, 1) = -0.5;
  EXPECT_EQ(particle_phi<2>(m, inverted, D, alpha, 10), 0);
}

}  // namespace
}  // namespace tear

namespace tear {
namespace {

// Small uniaxial strain e along n of an isotropic material: with the Lame parameters of E and
// nu (L = E nu / ((1 + nu)(1 - 2 nu)), mu), sigma = diag(L + 2 mu, L, ...) e, all tensile, so
// Phi = ((L + 2 mu)^2 + (d - 1) L^2) e^2 / sigma_c^2. (The QR model's own lambda is L + mu.)
template <int Dim>
void check_crack_onset_isotropic() {
  const double E = 1000, nu = 0.3;
  const MaterialParams m = make_material(Model::QrAniso, E, nu, 1);
  const Real L = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const Real alpha[2] = {0, 0};
  const Real sigma_c = 1;
  const Real expected =
      sigma_c / std::sqrt((L + 2 * mu) * (L + 2 * mu) + (Dim - 1) * L * L);
  const Real stretch = crack_onset_stretch<Dim>(m, Mat<Dim>::Identity(), alpha, sigma_c,
                                                Vec<Dim>::Unit(0));
  EXPECT_NEAR(stretch - 1, expected, 0.01 * expected);
  EXPECT_GT(crack_onset_stretch<Dim>(m, Mat<Dim>::Identity(), alpha, 4 * sigma_c,
                                     Vec<Dim>::Unit(0)),
            stretch);
  EXPECT_TRUE(std::isinf(crack_onset_stretch<Dim>(m, Mat<Dim>::Identity(), alpha, 1e9,
                                                  Vec<Dim>::Unit(0))));
}

TEST(CrackOnset, IsotropicSmallStrainMatchesLinearElasticity2D) {
  check_crack_onset_isotropic<2>();
}
TEST(CrackOnset, IsotropicSmallStrainMatchesLinearElasticity3D) {
  check_crack_onset_isotropic<3>();
}

// With alpha = -1 for fibers along x, pulling across them cracks sooner than along them.
TEST(CrackOnset, AcrossTheFibersBeforeAlongThem) {
  const MaterialParams m = make_material(Model::QrAniso, 100, 0.25, 2, 50);
  const Real alpha[2] = {-1, 0};
  const Real across =
      crack_onset_stretch<2>(m, Mat<2>::Identity(), alpha, 30, Vec<2>::Unit(1));
  const Real along = crack_onset_stretch<2>(m, Mat<2>::Identity(), alpha, 30, Vec<2>::Unit(0));
  EXPECT_GT(across, 1);
  EXPECT_GT(along, across);
  // At the onset Phi is 1.
  EXPECT_NEAR(particle_phi<2>(m, Mat<2>::Identity() + (across - 1) * Vec<2>::Unit(1) *
                                                          Vec<2>::Unit(1).transpose(),
                              Mat<2>::Identity(), alpha, 30),
              1, 1e-9);
}

}  // namespace
}  // namespace tear
