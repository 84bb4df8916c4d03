#include "tear/math/lanes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace tear {
namespace {

// Lanes give each lane the bits of the same scalar operations (the transfers rely on it for
// results that do not depend on the build's vector width): products, sums, broadcasts, lvalue
// subscripts, on random values over many magnitudes.
template <int N>
void expect_lanewise() {
  std::mt19937 rng(N);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-30, 30);
  auto value = [&] { return Real(std::ldexp(mantissa(rng), exponent(rng))); };
  for (int trial = 0; trial < 1000; ++trial) {
    Real a[N], b[N], c[N];
    Lanes<N> la{}, lb{}, lc{};
    for (int k = 0; k < N; ++k) {
      a[k] = value(), b[k] = value(), c[k] = value();
      la[k] = a[k], lb[k] = b[k], lc[k] = c[k];
    }
    const Real s = value();
    Lanes<N> r = la + lb * s;
    r += s * lc;
    r += la * lb;
    r = r - lc;
    for (int k = 0; k < N; ++k) {
      Real e = a[k] + b[k] * s;
      e += s * c[k];
      e += a[k] * b[k];
      e = e - c[k];
      EXPECT_EQ(std::memcmp(&e, &r[k], sizeof(Real)), 0) << "lane " << k << " of " << N;
    }
  }
}

TEST(Lanes, EachLaneRoundsAsTheScalarOperations) {
  expect_lanewise<2>();
  expect_lanewise<4>();
  // Made from four values, zero by default.
  const Lanes<4> made{1, 2, 3, 4}, zero{};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(made[k], Real(k + 1));
    EXPECT_EQ(zero[k], 0);
  }
}

}  // namespace
}  // namespace tear
