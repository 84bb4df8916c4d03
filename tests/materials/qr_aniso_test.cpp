#include "tear/materials/qr_aniso.h"

#include "material_test_util.h"

namespace tear {
namespace {

using namespace material_test;

// Several fiber frames: each test deformation gets its own random D.
TEST(QrAniso, StressIsGradientOfEnergy) {
  expect_stress_is_energy_gradient<2>(Model::QrAniso, 1);
  expect_stress_is_energy_gradient<3>(Model::QrAniso, 1);
}

TEST(QrAniso, DegradedStressIsGradientOfDegradedEnergy) {
  expect_stress_is_energy_gradient<2>(Model::QrAniso, 0.3);
  expect_stress_is_energy_gradient<3>(Model::QrAniso, 0.3);
  expect_stress_is_energy_gradient<2>(Model::QrAniso, 0.0);
  expect_stress_is_energy_gradient<3>(Model::QrAniso, 0.0);
}

// The analytic differential: a linear map of dF, the derivative of P to second order in the FD
// step near identity, and at the FD tolerance far from it (large, near-singular, inverted F),
// undamaged and damaged (both sides of J = 1 occur among the test deformations).
TEST(QrAniso, DifferentialIsLinearInDF) {
  for (Real g : {1.0, 0.3}) {
    expect_differential_is_linear<2>(Model::QrAniso, g);
    expect_differential_is_linear<3>(Model::QrAniso, g);
  }
}

TEST(QrAniso, DifferentialAgreesWithStressDifferencesAtSecondOrder) {
  for (Real g : {1.0, 0.3, 0.0}) {
    expect_differential_agrees_at_second_order<2>(Model::QrAniso, g);
    expect_differential_agrees_at_second_order<3>(Model::QrAniso, g);
  }
}

TEST(QrAniso, DifferentialMatchesFiniteDifferencesOfStress) {
  for (Real g : {1.0, 0.3, 0.0}) {
    expect_differential_matches_stress_differences<2>(Model::QrAniso, g);
    expect_differential_matches_stress_differences<3>(Model::QrAniso, g);
  }
}

// dP against central differences of the QR-based first_piola at one F (step h along dF).
template <int Dim>
void expect_dp_matches_at(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g,
                          const Mat<Dim>& dF, double h, double tol, const char* what) {
  const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF, g);
  const Mat<Dim> fd =
      (first_piola<Dim>(m, F + h * dF, D, g) - first_piola<Dim>(m, F - h * dF, D, g)) / (2 * h);
  EXPECT_LT((dP - fd).norm(), tol * (1 + dP.norm()))
      << what << " Dim " << Dim << " g " << g << "\nF =\n" << F << "\ndP =\n" << dP << "\nfd =\n" << fd;
}

// Where the QR's sign convention flips rows of R (a fiber pointing backwards: (F D) e1 with a
// negative first entry and nothing below it; in 3D also r22 < 0 before the flip), where a
// fiber is nearly squashed (r11 = |F a1| = 1e-3), and where the second fiber is (r12, r22 small):
// the energy is smooth in F there, and dP must follow the QR-based stress.
template <int Dim>
void expect_dp_at_qr_sign_flips() {
  std::mt19937_64 rng(71 + Dim);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 10, 4);
  for (int k = 0; k < 10; ++k) {
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    Mat<Dim> FD = Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.3);
    FD.col(0).setZero();
    FD(0, 0) = -0.9;  // r11 < 0 before the flip: Givens has nothing to rotate
    if constexpr (Dim == 3) FD(1, 1) = -std::abs(FD(1, 1));
    for (Real g : {1.0, 0.3}) {
      expect_dp_matches_at<Dim>(m, FD * D.transpose(), D, g, dF, 1e-6, 1e-6, "sign flip");
      Mat<Dim> squashed = FD;
      squashed(0, 0) = 1e-3;  // the fiber a1 at a thousandth of its length
      expect_dp_matches_at<Dim>(m, squashed * D.transpose(), D, g, dF, 1e-8, 1e-5, "squashed");
      if constexpr (Dim == 3) {
        Mat<Dim> second = FD;
        second(0, 1) = second(1, 1) = 2e-3;  // |F a2| ~ 3e-3
        expect_dp_matches_at<Dim>(m, second * D.transpose(), D, g, dF, 1e-8, 1e-5, "second");
      }
    }
  }
}

TEST(QrAniso, DifferentialFollowsTheStressAtQrSignFlipsAndSquashedFibers) {
  expect_dp_at_qr_sign_flips<2>();
  expect_dp_at_qr_sign_flips<3>();
}

// With damage the volumetric term switches at J = 1: just above, dP is the degraded tension
// derivative; just below, the full compression one. Checked on both sides at J = 1 +- 1e-3 with
// steps that do not cross, and the two one-sided derivatives differ by the switched part.
template <int Dim>
void expect_dp_on_both_sides_of_unit_volume() {
  std::mt19937_64 rng(83 + Dim);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 6, 2);
  for (int k = 0; k < 6; ++k) {
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    Mat<Dim> F0 = Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.2);
    F0 /= std::pow(F0.determinant(), Real(1) / Dim);  // J = 1
    for (Real g : {0.3, 0.0}) {
      const Mat<Dim> above = std::pow(1 + 1e-3, 1.0 / Dim) * F0;
      const Mat<Dim> below = std::pow(1 - 1e-3, 1.0 / Dim) * F0;
      expect_dp_matches_at<Dim>(m, above, D, g, dF, 1e-7, 1e-6, "J > 1");
      expect_dp_matches_at<Dim>(m, below, D, g, dF, 1e-7, 1e-6, "J < 1");
      const Mat<Dim> jump = stress_differential<Dim>(m, above, D, dF, g) -
                            stress_differential<Dim>(m, below, D, dF, g);
      const Mat<Dim> cof = cofactor<Dim>(F0);
      // lambda dJ cof F jumps by (g - 1) lambda dJ cof F (up to the O(1e-3) change of F).
      const Mat<Dim> expected = (g - 1) * m.lambda * cof.cwiseProduct(dF).sum() * cof;
      EXPECT_LT((jump - expected).norm(), 1e-2 * (m.lambda + expected.norm())) << "g " << g;
    }
  }
}

TEST(QrAniso, DamagedDifferentialOnBothSidesOfUnitVolume) {
  expect_dp_on_both_sides_of_unit_volume<2>();
  expect_dp_on_both_sides_of_unit_volume<3>();
}

// The supplement's route (§3.3): dP = -Q dQ^T P + Q dA R^-T - P dR^T R^-T with A = Q^T P R^T,
// dQ and dR from qr_differential, and dA the differential of the upper triangle of dPsi/dR R^T
// (here by central differences of A(R) along dR, so no further hand derivation enters). It
// divides by r_ii; where R is well conditioned it must equal the QR-free differential.
template <int Dim>
Mat<Dim> supplement_qr_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                    const Mat<Dim>& dF) {
  const Mat<Dim> FD = F * D, dFD = dF * D;
  Mat<Dim> Q, R, dQ, dR;
  qr_decompose<Dim>(FD, &Q, &R);
  qr_differential<Dim>(Q, R, dFD, &dQ, &dR);
  // A(R) = Q^T P(Q R) R^T depends on R only (rotation invariance): evaluate it with Q = I.
  const auto A_of = [&](const Mat<Dim>& Rr) {
    return Mat<Dim>(first_piola<Dim>(m, Mat<Dim>(Rr * D.transpose()), D) * D * Rr.transpose());
  };
  const double h = 1e-6;
  const Mat<Dim> dA = (A_of(R + h * dR) - A_of(R - h * dR)) / (2 * h);
  const Mat<Dim> PD = first_piola<Dim>(m, F, D) * D;  // the stress of F D
  const Mat<Dim> Rinv_t = R.inverse().transpose();
  const Mat<Dim> dPD =
      -Q * dQ.transpose() * PD + Q * dA * Rinv_t - PD * dR.transpose() * Rinv_t;
  return dPD * D.transpose();
}

template <int Dim>
void expect_supplement_route_agrees() {
  std::mt19937_64 rng(97 + Dim);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 6, 3);
  for (int k = 0; k < 10; ++k) {
    const Mat<Dim> F = Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.3);
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF);
    EXPECT_LT((supplement_qr_differential<Dim>(m, F, D, dF) - dP).norm(), 1e-5 * (1 + dP.norm()));
  }
}

TEST(QrAniso, DifferentialEqualsTheSupplementsQrRoute) {
  expect_supplement_route_agrees<2>();
  expect_supplement_route_agrees<3>();
}

TEST(QrAniso, ParametersShiftLambdaByMuAndScaleFibersByMu) {
  const MaterialParams q = make_material(Model::QrAniso, 1000, 0.25, 2, 4, 1);
  const double mu = 400, lambda = 400;
  EXPECT_DOUBLE_EQ(q.mu, mu);
  EXPECT_DOUBLE_EQ(q.lambda, lambda + mu);
  EXPECT_DOUBLE_EQ(q.kx, 4 * mu);
  EXPECT_DOUBLE_EQ(q.ky, mu);
  EXPECT_DOUBLE_EQ(wave_speed(q), std::sqrt((lambda + 2 * mu + 4 * mu) / 2));
}

// degrade_qr_stress turns the undegraded stress into the degraded one without a QR; it must
// agree with first_piola(..., g) in tension and compression, for any fiber frame and g.
template <int Dim>
void expect_degrade_qr_stress_matches() {
  std::mt19937_64 rng(12);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 10, 5);
  int tension = 0, compression = 0;
  for (int k = 0; k < 200; ++k) {
    const Mat<Dim> D = random_rotation<Dim>(rng);
    const Mat<Dim> F = Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.4);
    const Real J = F.determinant();
    if (J <= 0) continue;
    (J >= 1 ? tension : compression) += 1;
    const Mat<Dim> P = first_piola<Dim>(m, F, D);
    for (Real g : {0.0, 1e-3, 0.3, 1.0}) {
      const Mat<Dim> expected = first_piola<Dim>(m, F, D, g);
      EXPECT_LT((degrade_qr_stress<Dim>(m, F, P, g) - expected).norm(),
                1e-12 * (m.E + expected.norm()))
          << "g " << g << " J " << J;
    }
  }
  EXPECT_GT(tension, 30);
  EXPECT_GT(compression, 30);
}

TEST(QrAniso, DegradingTheStoredStressEqualsTheDegradedStress) {
  expect_degrade_qr_stress_matches<2>();
  expect_degrade_qr_stress_matches<3>();
}

// The paper's route to the stress (EQUATIONS.md §2): with F D = Q R and M = dPsi/dR (upper
// triangular), Abar is the symmetric matrix whose upper triangle is that of M R^T, and
// P = Q Abar R^{-T} D^T. It divides by r_ii; the library's form must agree where R is invertible.
template <int Dim>
Mat<Dim> paper_qr_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F * D, &Q, &R);
  const Real J = R.diagonal().prod();
  const Real s = -m.mu + m.lambda * (J - 1);
  Mat<Dim> M = m.mu * R;
  for (int i = 0; i < Dim; ++i) M(i, i) += s * J / R(i, i);
  M(0, 0) += m.kx * (R(0, 0) - 1);
  if (Dim == 3) {
    const Real n2 = std::hypot(R(0, 1), R(1, 1));
    M(0, 1) += m.ky * (n2 - 1) * R(0, 1) / n2;
    M(1, 1) += m.ky * (n2 - 1) * R(1, 1) / n2;
  }
  const Mat<Dim> MRt = M * R.transpose();
  Mat<Dim> Abar;
  for (int i = 0; i < Dim; ++i)
    for (int j = i; j < Dim; ++j) Abar(i, j) = Abar(j, i) = MRt(i, j);
  return Q * Abar * R.inverse().transpose() * D.transpose();
}

template <int Dim>
void expect_paper_stress_agrees() {
  std::mt19937_64 rng(13);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 6, 3);
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> D = random_rotation<Dim>(rng);
    const Mat<Dim> P = first_piola<Dim>(m, F, D);
    EXPECT_LT((paper_qr_stress<Dim>(m, F, D) - P).norm(), 1e-8 * (1 + P.norm()));
  }
}

TEST(QrAniso, DivisionFreeStressEqualsThePaperForm) {
  expect_paper_stress_agrees<2>();
  expect_paper_stress_agrees<3>();
}

TEST(QrAniso, StressStaysFiniteAndContinuousAsR11GoesToZero) {
  // Fiber a1 = x; F squashes the fiber to length r11 while other directions stay regular.
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 0, 3);
  const Mat<3> D = Mat<3>::Identity();
  auto F_at = [](double r11) {
    Mat<3> F;
    F << r11, 0.4, 0.1,  //
        0, 1.1, 0.3,     //
        0, 0.2, 0.9;
    return F;
  };
  const Mat<3> P0 = first_piola<3>(m, F_at(0), D);
  ASSERT_TRUE(P0.allFinite());
  for (double r11 : {1e-4, 1e-8, 1e-12, 1e-30, 1e-300}) {
    const Mat<3> P = first_piola<3>(m, F_at(r11), D);
    ASSERT_TRUE(P.allFinite()) << r11;
    EXPECT_LT((P - P0).norm(), 1e4 * r11 * (1 + P0.norm())) << r11;
  }
  // With fiber stiffness the stress is still finite at r11 = 0 (2D and 3D).
  const MaterialParams mf = make_material(Model::QrAniso, 1000, 0.3, 1, 20, 3);
  EXPECT_TRUE(first_piola<3>(mf, F_at(0), D).allFinite());
  Mat<2> F2;
  F2 << 0, 0.5, 0, 1.2;
  EXPECT_TRUE(first_piola<2>(mf, F2, Mat<2>::Identity()).allFinite());
  EXPECT_TRUE(first_piola<3>(mf, Mat<3>::Zero(), D).allFinite());
}

TEST(QrAniso, FiberStiffnessAddsToTheUniaxialModulusAlongTheFiber) {
  const double E = 1000, nu = 0.25, gamma1 = 8, gamma2 = 3;
  const MaterialParams m = make_material(Model::QrAniso, E, nu, 1, gamma1, gamma2);
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  std::mt19937_64 rng(23);
  const Mat<3> D = random_rotation<3>(rng);
  const double e = 1e-6;
  for (int f = 0; f < 3; ++f) {
    const Vec<3> a = D.col(f);
    const Mat<3> F = Mat<3>::Identity() + e * a * a.transpose();
    const double normal_stress = a.dot(first_piola<3>(m, F, D) * a);
    const double fiber = f == 0 ? gamma1 * mu : f == 1 ? gamma2 * mu : 0;
    EXPECT_NEAR(normal_stress / e, lambda + 2 * mu + fiber, 1e-3 * (lambda + 2 * mu)) << f;
  }
  // 2D: only a1 is stiffened.
  const MaterialParams m2 = make_material(Model::QrAniso, E, nu, 1, gamma1, 0);
  Mat<2> D2;
  D2 << 0.6, -0.8, 0.8, 0.6;
  const Vec<2> a1 = D2.col(0), a2 = D2.col(1);
  const double s1 =
      a1.dot(first_piola<2>(m2, Mat<2>::Identity() + e * a1 * a1.transpose(), D2) * a1);
  const double s2 =
      a2.dot(first_piola<2>(m2, Mat<2>::Identity() + e * a2 * a2.transpose(), D2) * a2);
  EXPECT_NEAR(s1 / e, lambda + 2 * mu + gamma1 * mu, 1e-3 * lambda);
  EXPECT_NEAR(s2 / e, lambda + 2 * mu, 1e-3 * lambda);
}

TEST(QrAniso, DegradationSoftensTensionButNotCompressionVolume) {
  // A fully damaged particle (g = r) carries r of the isotropic stress in tension (J >= 1),
  // and in compression r of the mu terms plus the full volumetric (lambda) term. Fiber
  // terms are never degraded. Checked on general F (shear + stretch), 2D and 3D.
  const Real r = Real(0.001);
  const MaterialParams m = make_material(Model::QrAniso, 1000, 0.3, 1, 5, 2);
  MaterialParams iso = m, mu_only = m;
  iso.kx = iso.ky = 0;
  mu_only.kx = mu_only.ky = 0;
  mu_only.lambda = 0;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (int k = 0; k < 20; ++k) {
    Mat<3> F = Mat<3>::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += Real(u(rng));
    const Mat<3> D = random_rotation<3>(rng);
    for (Real scale : {Real(1.06), Real(0.94)}) {  // J > 1 and J < 1
      const Mat<3> G = scale * F;
      const bool tension = G.determinant() >= 1;
      const Mat<3> P_iso = first_piola<3>(iso, G, D), P_mu = first_piola<3>(mu_only, G, D);
      const Mat<3> expected = tension ? Mat<3>(r * P_iso) : Mat<3>(r * P_mu + (P_iso - P_mu));
      EXPECT_LT((first_piola<3>(iso, G, D, r) - expected).norm(), 1e-10 * P_iso.norm())
          << (tension ? "tension" : "compression");
      // The fibers add the same stress at any damage.
      const Mat<3> fiber_0 = first_piola<3>(m, G, D) - P_iso;
      const Mat<3> fiber_r = first_piola<3>(m, G, D, r) - first_piola<3>(iso, G, D, r);
      EXPECT_LT((fiber_r - fiber_0).norm(), 1e-10 * (1 + fiber_0.norm()));
      if (k == 0) {
        EXPECT_GT(fiber_0.norm(), 0.1 * P_iso.norm());  // not vacuous
      }
    }
  }
  const MaterialParams iso2 = make_material(Model::QrAniso, 1000, 0.3, 1);
  const Mat<2> stretch = Vec<2>(1.05, 1.02).asDiagonal();
  EXPECT_LT((first_piola<2>(iso2, stretch, Mat<2>::Identity(), r) -
             r * first_piola<2>(iso2, stretch, Mat<2>::Identity()))
                .norm(),
            1e-10 * first_piola<2>(iso2, stretch, Mat<2>::Identity()).norm());
}

}  // namespace
}  // namespace tear
