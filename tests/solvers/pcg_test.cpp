// Jacobi-PCG: solves SPD systems to the requested relative residual, in at most n steps
// (exact arithmetic), leaves excluded unknowns alone, and handles b = 0.
#include "tear/solvers/pcg.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

namespace tear {
namespace {

using MatX = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;
using VecX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

// A 1D Laplacian plus a varying positive diagonal (like the damage system A + B).
MatX damage_like_matrix(int n) {
  MatX K = MatX::Zero(n, n);
  for (int i = 0; i < n; ++i) K(i, i) = 1 + 0.5 * std::sin(i);
  for (int i = 0; i < n; ++i) {
    if (i + 1 < n) {
      K(i, i) += 3, K(i + 1, i + 1) += 3;
      K(i, i + 1) -= 3, K(i + 1, i) -= 3;
    }
  }
  return K;
}

std::vector<Real> to_std(const VecX& v) { return std::vector<Real>(v.data(), v.data() + v.size()); }

TEST(Pcg, SolvesAnSpdSystemToTheRequestedResidual) {
  const int n = 40;
  const MatX K = damage_like_matrix(n);
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  VecX b(n);
  for (int i = 0; i < n; ++i) b[i] = u(rng);
  const VecX exact = K.ldlt().solve(b);
  std::vector<Real> inv_diag(n), x(n, 0);
  for (int i = 0; i < n; ++i) inv_diag[i] = 1 / K(i, i);
  auto apply = [&](const std::vector<Real>& in, std::vector<Real>& out) {
    const VecX y = K * Eigen::Map<const VecX>(in.data(), n);
    out.assign(y.data(), y.data() + n);
  };
  for (double tol : {1e-4, 1e-8, 1e-12}) {
    std::fill(x.begin(), x.end(), 0);
    const PcgResult r = pcg_solve(apply, to_std(b), inv_diag, tol, 1000, &x);
    EXPECT_TRUE(r.converged);
    EXPECT_LE(r.residual, tol);
    EXPECT_LE(r.iterations, n);  // CG terminates in n steps in exact arithmetic
    const VecX xe = Eigen::Map<const VecX>(x.data(), n);
    EXPECT_NEAR((b - K * xe).norm() / b.norm(), r.residual, 1e-12);
    EXPECT_LT((xe - exact).norm(), 1e3 * tol * exact.norm());
  }
  // A good initial guess (the solution) needs no iteration.
  x = to_std(exact);
  EXPECT_EQ(pcg_solve(apply, to_std(b), inv_diag, 1e-8, 1000, &x).iterations, 0);
  // The iteration cap is honoured and reported.
  std::fill(x.begin(), x.end(), 0);
  const PcgResult capped = pcg_solve(apply, to_std(b), inv_diag, 1e-14, 3, &x);
  EXPECT_EQ(capped.iterations, 3);
  EXPECT_FALSE(capped.converged);
}

TEST(Pcg, ExcludedUnknownsAreLeftAloneAndZeroRhsGivesZero) {
  const int n = 10;
  MatX K = damage_like_matrix(n);
  // Unknown 4 does not take part: decoupled, inv_diag 0; its value must survive.
  K.row(4).setZero();
  K.col(4).setZero();
  std::vector<Real> inv_diag(n), x(n, 0), b(n, 1);
  for (int i = 0; i < n; ++i) inv_diag[i] = i == 4 ? 0 : 1 / K(i, i);
  b[4] = 0;
  x[4] = 7;
  auto apply = [&](const std::vector<Real>& in, std::vector<Real>& out) {
    const VecX y = K * Eigen::Map<const VecX>(in.data(), n);
    out.assign(y.data(), y.data() + n);
  };
  EXPECT_TRUE(pcg_solve(apply, b, inv_diag, 1e-10, 100, &x).converged);
  EXPECT_EQ(x[4], 7);
  std::vector<Real> zero(n, 0);
  x.assign(n, 1);
  const PcgResult r = pcg_solve(apply, zero, inv_diag, 1e-10, 100, &x);
  EXPECT_EQ(r.iterations, 0);
  for (int i = 0; i < n; ++i) EXPECT_EQ(x[i], i == 4 ? 1 : 0);
}

}  // namespace
}  // namespace tear
