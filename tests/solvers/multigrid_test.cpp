// Geometric multigrid on lattice points (solvers/multigrid.h): its V-cycle is a symmetric
// positive definite operator, CG preconditioned by it takes nearly the same iterations at any
// resolution (Jacobi's double as the spacing halves) on an irregular domain with a varying
// coefficient, constrained directions stay zero, and the bits do not depend on the threads.
#include "tear/exec/threads.h"
#include "tear/solvers/multigrid.h"
#include "tear/solvers/pcg.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tear {
namespace {

using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Points of an n x n lattice inside a disk with a square hole off its centre (an irregular
// domain), and on them the operator of -div(k grad u) + m u with 9-point couplings (reach 1),
// k varying tenfold across the domain, a small mass m; `block` copies of it per point, coupled
// by a fraction `coupling` of the diagonal between components.
struct Problem {
  std::vector<IVec<2>> points;
  Matrix A;
};

Problem lattice_problem(int n, int block, double coupling = 0) {
  Problem p;
  std::vector<int> index(size_t(n * n), -1);
  auto inside = [n](int i, int j) {
    const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5;
    const bool hole = std::abs(x - 0.12) < 0.1 && std::abs(y + 0.05) < 0.1;
    return x * x + y * y < 0.24 && !hole;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (inside(i, j)) {
        index[size_t(j * n + i)] = int(p.points.size());
        p.points.push_back(IVec<2>(i, j));
      }
  const double h = 1.0 / n, mass = 1e-3;
  std::vector<Eigen::Triplet<double>> t;
  for (size_t k = 0; k < p.points.size(); ++k) {
    const IVec<2> a = p.points[k];
    double diag = mass * h * h;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        if (di == 0 && dj == 0) continue;
        const int i = a[0] + di, j = a[1] + dj;
        if (i < 0 || j < 0 || i >= n || j >= n) continue;
        const int other = index[size_t(j * n + i)];
        if (other < 0) continue;
        const double xm = (a[0] + 0.5 * di + 0.5) / n;
        const double k_edge = (1 + 9 * xm) * (di != 0 && dj != 0 ? 0.25 : 1.0);
        diag += k_edge;
        for (int c = 0; c < block; ++c)
          t.emplace_back(int(k) * block + c, other * block + c, -k_edge);
      }
    for (int c = 0; c < block; ++c)
      for (int e = 0; e < block; ++e)
        t.emplace_back(int(k) * block + c, int(k) * block + e, c == e ? diag : coupling * diag);
  }
  p.A.resize(long(p.points.size()) * block, long(p.points.size()) * block);
  p.A.setFromTriplets(t.begin(), t.end());
  return p;
}

int cg_iterations(const Problem& p, int block, bool multigrid) {
  const size_t n = size_t(p.A.rows());
  Matrix A = p.A;
  const LatticeMultigrid<2> mg(p.points, block, 1, Matrix(p.A));
  std::vector<Real> b(n), x(n, 0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Real& v : b) v = Real(u(rng));
  Eigen::VectorXd xin, yout;
  const auto apply = [&](const std::vector<Real>& in, std::vector<Real>& out) {
    xin = Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, 1>>(in.data(), long(n)).cast<double>();
    sparse_multiply(A, xin, yout);
    for (size_t i = 0; i < n; ++i) out[i] = Real(yout[long(i)]);
  };
  const auto precondition = [&](const std::vector<Real>& r, std::vector<Real>& z) {
    if (!multigrid) {
      for (size_t i = 0; i < n; ++i) z[i] = r[i] / Real(A.coeff(long(i), long(i)));
      return;
    }
    xin = Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, 1>>(r.data(), long(n)).cast<double>();
    mg.apply(xin, yout);
    for (size_t i = 0; i < n; ++i) z[i] = Real(yout[long(i)]);
  };
  const PcgResult r =
      pcg_solve(apply, precondition, [](size_t) { return true; }, b, 1e-8, 100000, &x);
  EXPECT_TRUE(r.converged);
  return r.iterations;
}

TEST(Multigrid, CgIterationsStayNearlyConstantAsTheLatticeRefines) {
  int jac[3], mg[3];
  for (int k = 0; k < 3; ++k) {
    const Problem p = lattice_problem(64 << k, 1);  // all above the directly factored size
    jac[k] = cg_iterations(p, 1, false);
    mg[k] = cg_iterations(p, 1, true);
    std::printf("n %d (%zu points): CG iterations Jacobi %d, multigrid %d\n", 64 << k,
                p.points.size(), jac[k], mg[k]);
  }
  for (int k = 1; k < 3; ++k) {
    EXPECT_GT(double(jac[k]) / jac[k - 1], 1.7);
    EXPECT_LE(mg[k], mg[k - 1] + 3);
  }
  EXPECT_LT(4 * mg[2], jac[2]);
}

TEST(Multigrid, CycleIsSymmetricPositiveAndKeepsConstrainedDirectionsZero) {
  // Two unknowns a point, coupled; every fifth point has its first direction constrained (its
  // rows for it replaced by the identity, as the implicit integrator does).
  Problem p = lattice_problem(48, 2, 0.3);
  const size_t points = p.points.size();
  std::vector<double> free(points * 4, 0.0);
  std::vector<bool> held(points);
  for (size_t k = 0; k < points; ++k) {
    held[k] = k % 5 == 0;
    free[k * 4 + 0] = held[k] ? 0 : 1;  // column-major 2x2: (0,0)
    free[k * 4 + 3] = 1;                // (1,1)
  }
  std::vector<Eigen::Triplet<double>> t;
  for (long i = 0; i < p.A.rows(); ++i)
    for (Matrix::InnerIterator it(p.A, i); it; ++it) {
      const bool hi = held[size_t(i / 2)] && i % 2 == 0;
      const bool hj = held[size_t(it.col() / 2)] && it.col() % 2 == 0;
      if (!hi && !hj) t.emplace_back(int(i), int(it.col()), it.value());
    }
  for (size_t k = 0; k < points; ++k)
    if (held[k]) t.emplace_back(int(2 * k), int(2 * k), 1.0);
  Matrix A(p.A.rows(), p.A.cols());
  A.setFromTriplets(t.begin(), t.end());
  const LatticeMultigrid<2> mg(p.points, 2, 1, std::move(A), free);
  EXPECT_GE(mg.levels(), 2);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  auto random_free = [&]() {
    Eigen::VectorXd v(long(2 * points));
    for (long i = 0; i < v.size(); ++i) v[i] = held[size_t(i / 2)] && i % 2 == 0 ? 0 : normal(rng);
    return v;
  };
  const Eigen::VectorXd d = random_free(), e = random_free();
  Eigen::VectorXd Md, Me;
  mg.apply(d, Md);
  mg.apply(e, Me);
  EXPECT_NEAR(e.dot(Md), d.dot(Me), 1e-10 * d.dot(Md));
  EXPECT_GT(d.dot(Md), 0);
  for (size_t k = 0; k < points; ++k)
    if (held[k]) {
      EXPECT_EQ(Md[long(2 * k)], 0.0);
    }
}

TEST(Multigrid, SameBitsForOneAndTwoThreads) {
  const Problem p = lattice_problem(64, 1);
  Eigen::VectorXd r(p.A.rows());
  for (long i = 0; i < r.size(); ++i) r[i] = std::sin(0.37 * double(i));
  auto run = [&](int threads) {
    const ThreadLimit limit(threads);
    const LatticeMultigrid<2> mg(p.points, 1, 1, Matrix(p.A));
    Eigen::VectorXd z;
    mg.apply(r, z);
    return z;
  };
  const Eigen::VectorXd a = run(1), b = run(2);
  for (long i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << i;
}

TEST(Multigrid, RefusesAReachItCannotColour) {
  const Problem p = lattice_problem(16, 1);
  EXPECT_THROW(LatticeMultigrid<2>(p.points, 1, 4, Matrix(p.A)), std::invalid_argument);
}

}  // namespace
}  // namespace tear
