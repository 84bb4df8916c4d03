#include "tear/math/qr.h"
#include "tear/math/svd.h"

#include <gtest/gtest.h>

#include <random>

namespace tear {
namespace {

template <int Dim>
Mat<Dim> random_matrix(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  Mat<Dim> A;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) A(i, j) = u(rng);
  return A;
}

template <int Dim>
void expect_valid_qr(const Mat<Dim>& A) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(A, &Q, &R);
  EXPECT_LT((Q * R - A).norm(), 1e-12 * (1 + A.norm()));
  EXPECT_LT((Q.transpose() * Q - Mat<Dim>::Identity()).norm(), 1e-13);
  EXPECT_NEAR(Q.determinant(), 1.0, 1e-13);
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < i; ++j) EXPECT_EQ(R(i, j), 0.0);
  EXPECT_GE(R(0, 0), 0.0);
  if (Dim == 3) {
    EXPECT_GE(R(1, 1), 0.0);
  }
  EXPECT_NEAR(R.diagonal().prod(), A.determinant(), 1e-12 * (1 + std::abs(A.determinant())));
}

TEST(Qr, RandomMatricesFactorWithSignConvention) {
  std::mt19937_64 rng(7);
  for (int k = 0; k < 200; ++k) {
    expect_valid_qr<2>(random_matrix<2>(rng));
    expect_valid_qr<3>(random_matrix<3>(rng));
  }
}

TEST(Qr, InvertedMatrixPutsTheSignOnTheLastDiagonal) {
  Mat<3> A = Mat<3>::Identity();
  A(0, 0) = -1;  // a reflection: det -1
  Mat<3> Q, R;
  qr_decompose<3>(A, &Q, &R);
  EXPECT_GT(R(0, 0), 0);
  EXPECT_GT(R(1, 1), 0);
  EXPECT_LT(R(2, 2), 0);
  Mat<2> B = Mat<2>::Identity();
  B(1, 1) = -3;
  Mat<2> Q2, R2;
  qr_decompose<2>(B, &Q2, &R2);
  EXPECT_DOUBLE_EQ(R2(1, 1), -3);
}

TEST(Qr, SingularAndZeroColumnsAreHandled) {
  Mat<3> A;
  A << 0, 1, 2,  //
      0, 3, 4,   //
      0, 5, 7;
  expect_valid_qr<3>(A);  // first column zero: r11 = 0
  expect_valid_qr<3>(Mat<3>::Zero());
  Mat<3> B;
  B << -1, 2, 0,  //
      0, 0, 1,    //
      0, 0, 3;
  expect_valid_qr<3>(B);  // negative r11 with nothing below it: the flip must fix it
  Mat<2> C;
  C << -2, 1, 0, 0;
  expect_valid_qr<2>(C);
}

TEST(Cofactor, EqualsDeterminantTimesInverseTranspose) {
  std::mt19937_64 rng(3);
  for (int k = 0; k < 50; ++k) {
    const Mat<3> A = random_matrix<3>(rng);
    EXPECT_LT((cofactor<3>(A) - A.determinant() * A.inverse().transpose()).norm(), 1e-10);
    const Mat<2> B = random_matrix<2>(rng);
    EXPECT_LT((cofactor<2>(B) - B.determinant() * B.inverse().transpose()).norm(), 1e-10);
  }
}

TEST(SignedSvd, RotationsAndNegativeLastValueForInversion) {
  std::mt19937_64 rng(11);
  int inverted = 0;
  for (int k = 0; k < 100; ++k) {
    const Mat<3> F = random_matrix<3>(rng);
    Mat<3> U, V;
    Vec<3> s;
    signed_svd<3>(F, &U, &s, &V);
    EXPECT_NEAR(U.determinant(), 1, 1e-12);
    EXPECT_NEAR(V.determinant(), 1, 1e-12);
    EXPECT_LT((U * s.asDiagonal() * V.transpose() - F).norm(), 1e-12);
    EXPECT_GE(s[0], std::abs(s[2]));
    EXPECT_GE(s[1], 0);
    if (F.determinant() < 0) {
      EXPECT_LT(s[2], 0);
      ++inverted;
    }
    EXPECT_NEAR(polar_rotation_svd<3>(F).determinant(), 1, 1e-12);
  }
  EXPECT_GT(inverted, 10);
}

// qr_differential (supplement §3.4, Jiang et al. 2017 §1) against central differences of
// qr_decompose along dA: dQ, dR agree; Q^T dQ is skew and dR upper triangular by construction.
template <int Dim>
void expect_qr_differential_matches_differences() {
  std::mt19937_64 rng(17 + Dim);
  int checked = 0;
  for (int k = 0; k < 100; ++k) {
    const Mat<Dim> A = random_matrix<Dim>(rng), dA = random_matrix<Dim>(rng);
    Mat<Dim> Q, R;
    qr_decompose<Dim>(A, &Q, &R);
    if (R(0, 0) < 0.2 || (Dim == 3 && R(1, 1) < 0.2)) continue;  // near the non-smooth set
    Mat<Dim> dQ, dR, Qp, Rp, Qm, Rm;
    qr_differential<Dim>(Q, R, dA, &dQ, &dR);
    const double h = 1e-6;
    qr_decompose<Dim>(A + h * dA, &Qp, &Rp);
    qr_decompose<Dim>(A - h * dA, &Qm, &Rm);
    EXPECT_LT(((Qp - Qm) / (2 * h) - dQ).norm(), 1e-6 * (1 + dQ.norm()));
    EXPECT_LT(((Rp - Rm) / (2 * h) - dR).norm(), 1e-6 * (1 + dR.norm()));
    EXPECT_LT((dQ * R + Q * dR - dA).norm(), 1e-12 * (1 + dA.norm()));  // d(QR) = dA
    ++checked;
  }
  EXPECT_GT(checked, 40);
}

TEST(Qr, DifferentialMatchesDifferencesOfTheFactors) {
  expect_qr_differential_matches_differences<2>();
  expect_qr_differential_matches_differences<3>();
}

}  // namespace
}  // namespace tear
