#include "tear/kernels/bspline.h"

#include <gtest/gtest.h>

#include <random>

namespace tear {
namespace {

template <int Order>
void check_kernel_properties() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(2.0, 30.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double x = u(rng);
    const BSpline1D<Order> s(x);
    double sum_w = 0, sum_wx = 0, sum_dw = 0, sum_dwx = 0, sum_ddw = 0, sum_ddwx = 0;
    for (int k = 0; k < s.kWidth; ++k) {
      const double xi = s.base + k;
      sum_w += s.w[k], sum_wx += s.w[k] * xi;
      sum_dw += s.dw[k], sum_dwx += s.dw[k] * xi;
      sum_ddw += s.ddw[k], sum_ddwx += s.ddw[k] * xi;
      EXPECT_GE(s.w[k], -1e-15);
    }
    // Partition of unity and linear reproduction, and their derivatives.
    EXPECT_NEAR(sum_w, 1, 1e-13);
    EXPECT_NEAR(sum_wx, x, 1e-12);
    EXPECT_NEAR(sum_dw, 0, 1e-12);
    EXPECT_NEAR(sum_dwx, 1, 1e-12);
    EXPECT_NEAR(sum_ddw, 0, 1e-12);
    EXPECT_NEAR(sum_ddwx, 0, 1e-12);
    if (Order == 2 || Order == 3) {
      // sum_i w_i (x_i - x)^2 = 1 / kInvD (grid units): the APIC D matrix.
      double m2 = 0;
      for (int k = 0; k < s.kWidth; ++k) m2 += s.w[k] * (s.base + k - x) * (s.base + k - x);
      EXPECT_NEAR(m2, 1.0 / BSpline1D<Order>::kInvD, 1e-12);
    }
  }
}

template <int Order>
void check_derivatives_by_fd() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(2.0, 30.0);
  const double h = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    const double x = u(rng);
    const BSpline1D<Order> s(x), sp(x + h), sm(x - h);
    if (sp.base != s.base || sm.base != s.base) continue;  // straddles a knot: skip
    for (int k = 0; k < s.kWidth; ++k) {
      EXPECT_NEAR(s.dw[k], (sp.w[k] - sm.w[k]) / (2 * h), 1e-7) << "order " << Order;
      if (Order >= 2) {
        EXPECT_NEAR(s.ddw[k], (sp.dw[k] - sm.dw[k]) / (2 * h), 1e-6);
      }
    }
  }
}

TEST(BSpline, LinearPartitionOfUnityAndLinearReproduction) { check_kernel_properties<1>(); }
TEST(BSpline, QuadraticPartitionOfUnityAndLinearReproduction) { check_kernel_properties<2>(); }
TEST(BSpline, CubicPartitionOfUnityAndLinearReproduction) { check_kernel_properties<3>(); }
TEST(BSpline, LinearDerivativesMatchFiniteDifferences) { check_derivatives_by_fd<1>(); }
TEST(BSpline, QuadraticDerivativesMatchFiniteDifferences) { check_derivatives_by_fd<2>(); }
TEST(BSpline, CubicDerivativesMatchFiniteDifferences) { check_derivatives_by_fd<3>(); }

TEST(BSpline, CubicReproducesQuadraticsSecondDerivative) {
  // The cubic spline reproduces quadratics up to a constant: sum N_i''(x) x_i^2 = 2.
  for (double x : {3.1, 4.5, 7.99, 10.0}) {
    const BSpline1D<3> s(x);
    double lap = 0;
    for (int k = 0; k < s.kWidth; ++k) lap += s.ddw[k] * (s.base + k) * (s.base + k);
    EXPECT_NEAR(lap, 2.0, 1e-12);
  }
}

TEST(BSpline, SupportStartsAtTheDocumentedBaseNode) {
  EXPECT_EQ(BSpline1D<1>(3.7).base, 3);
  EXPECT_EQ(BSpline1D<2>(3.7).base, 3);
  EXPECT_EQ(BSpline1D<2>(3.2).base, 2);
  EXPECT_EQ(BSpline1D<3>(3.7).base, 2);
}

}  // namespace
}  // namespace tear
