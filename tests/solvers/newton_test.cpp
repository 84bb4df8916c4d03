// newton_minimize on energies with known minimisers: a strictly convex quartic (Newton converges
// quadratically, the energy never rises), one with a non-convex term whose Hessian is projected,
// and fixed unknowns held where they start.
#include "tear/solvers/newton.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace tear {
namespace {

// E(x) = sum_i a_i/4 x_i^4 + 1/2 |x - c|^2 + b/2 sum_i (x_i - x_{i+1})^2: strictly convex, its
// Hessian diag(3 a x^2 + 1) + b L is positive definite. `projected`: drop the coupling's
// off-diagonal part to test a Hessian that is only an approximation (no longer quadratic).
struct Quartic {
  std::vector<Real> a, c;
  Real b = 0.5;
  std::vector<bool> fixed;
  std::vector<Real> x_h;  // x at prepare_hessian

  size_t n() const { return a.size(); }
  double energy(const std::vector<Real>& x) {
    double e = 0;
    for (size_t i = 0; i < n(); ++i) {
      e += a[i] / 4 * std::pow(x[i], 4) + 0.5 * (x[i] - c[i]) * (x[i] - c[i]);
      if (i + 1 < n()) e += b / 2 * (x[i] - x[i + 1]) * (x[i] - x[i + 1]);
    }
    return e;
  }
  void gradient(const std::vector<Real>& x, std::vector<Real>& g) {
    for (size_t i = 0; i < n(); ++i) {
      g[i] = a[i] * std::pow(x[i], 3) + (x[i] - c[i]);
      if (i + 1 < n()) g[i] += b * (x[i] - x[i + 1]);
      if (i > 0) g[i] += b * (x[i] - x[i - 1]);
    }
    for (size_t i = 0; i < n(); ++i)
      if (fixed[i]) g[i] = 0;
  }
  double residual(const std::vector<Real>& g) const {
    double s = 0;
    for (Real v : g) s += v * v;
    return std::sqrt(s);
  }
  void prepare_hessian(const std::vector<Real>& x) { x_h = x; }
  void apply_hessian(const std::vector<Real>& d, std::vector<Real>& y) const {
    for (size_t i = 0; i < n(); ++i) {
      if (fixed[i]) {
        y[i] = 0;
        continue;
      }
      y[i] = (3 * a[i] * x_h[i] * x_h[i] + 1) * d[i];
      auto dd = [&](size_t j) { return fixed[j] ? Real(0) : d[j]; };
      if (i + 1 < n()) y[i] += b * (d[i] - dd(i + 1));
      if (i > 0) y[i] += b * (d[i] - dd(i - 1));
    }
  }
  void precondition(const std::vector<Real>& r, std::vector<Real>& z) const {
    for (size_t i = 0; i < n(); ++i) z[i] = fixed[i] ? 0 : r[i] / (3 * a[i] * x_h[i] * x_h[i] + 1 + 2 * b);
  }
  bool active(size_t i) const { return !fixed[i]; }
};

Quartic make_quartic(size_t n) {
  Quartic q;
  for (size_t i = 0; i < n; ++i) {
    q.a.push_back(Real(1 + (i % 3)));
    q.c.push_back(Real(3 * std::sin(double(i))));
  }
  q.fixed.assign(n, false);
  return q;
}

TEST(Newton, ConvergesQuadraticallyAndNeverRaisesTheEnergy) {
  Quartic q = make_quartic(40);
  std::vector<Real> x(40, Real(0));
  NewtonSettings s;
  s.tolerance = 1e-12;
  s.cg_tolerance = 1e-12;
  s.max_iterations = 50;
  const NewtonResult r = newton_minimize(q, &x, s);
  ASSERT_TRUE(r.converged) << r.residual;
  for (size_t k = 1; k < r.energies.size(); ++k) EXPECT_LE(r.energies[k], r.energies[k - 1]);
  // Quadratic: once the residual is small, the next is below C times its square.
  int quadratic_steps = 0;
  for (size_t k = 0; k + 1 < r.residuals.size(); ++k)
    if (r.residuals[k] < 1e-1 && r.residuals[k + 1] > 1e-14) {
      EXPECT_LT(r.residuals[k + 1], 10 * r.residuals[k] * r.residuals[k]) << "step " << k;
      ++quadratic_steps;
    }
  EXPECT_GE(quadratic_steps, 1);
  // The minimiser: the gradient vanishes.
  std::vector<Real> g(40);
  q.gradient(x, g);
  EXPECT_LT(q.residual(g), 1e-12);
}

TEST(Newton, LineSearchHalvesStepsThatRaiseTheEnergy) {
  // Far from the minimum the quartic's full Newton step overshoots: the energy must still fall.
  Quartic q = make_quartic(10);
  for (Real& c : q.c) c *= 100;
  std::vector<Real> x(10, Real(0.01));
  NewtonSettings s;
  s.tolerance = 1e-10;
  s.cg_tolerance = 1e-12;
  s.max_iterations = 100;
  const NewtonResult r = newton_minimize(q, &x, s);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.line_search_cuts, 0);
  for (size_t k = 1; k < r.energies.size(); ++k) EXPECT_LE(r.energies[k], r.energies[k - 1]);
}

TEST(Newton, FixedUnknownsStayAndTheOthersMinimise) {
  Quartic q = make_quartic(20);
  q.fixed[0] = q.fixed[7] = true;
  std::vector<Real> x(20, Real(0));
  x[0] = 2, x[7] = -1;
  NewtonSettings s;
  s.tolerance = 1e-11;
  s.cg_tolerance = 1e-12;
  const NewtonResult r = newton_minimize(q, &x, s);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(x[0], 2);
  EXPECT_EQ(x[7], -1);
  std::vector<Real> g(20);
  q.gradient(x, g);
  EXPECT_LT(q.residual(g), 1e-11);
}

TEST(Newton, StopsAtTheIterationLimitUnconverged) {
  Quartic q = make_quartic(10);
  std::vector<Real> x(10, Real(0));
  NewtonSettings s;
  s.tolerance = 1e-14;
  s.max_iterations = 1;
  const NewtonResult r = newton_minimize(q, &x, s);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(r.residuals.size(), 2u);
}

}  // namespace
}  // namespace tear
