// kernels/: B-spline interpolation kernels (linear, quadratic, cubic) with first and second
// derivatives. Owns only 1-D weights in grid units; knows nothing of particles or grids.
#pragma once

#include "tear/math/types.h"

#include <cmath>

namespace tear {

// floor(x) as an int without a libm call (std::floor is out of line without SSE4.1).
inline int floor_int(Real x) {
  const int i = int(x);
  return i - int(x < Real(i));
}

// 1-D B-spline of order `Order` (1 linear, 2 quadratic, 3 cubic) evaluated at a particle.
// `x` is the particle coordinate in grid units (position / dx, relative to node 0).
// Nodes base .. base + Order receive weights w[k]; dw and ddw are derivatives with respect
// to x in grid units (divide by dx, dx^2 for world units).
template <int Order>
struct BSpline1D {
  static constexpr int kWidth = Order + 1;
  int base = 0;
  Real w[kWidth], dw[kWidth], ddw[kWidth];

  // MLS/APIC inertia-like scale: sum_i w_i (x_i - x)(x_i - x)^T = (1 / kInvD) dx^2 I.
  // Quadratic 4/dx^2, cubic 3/dx^2 (EQUATIONS.md §1 "Implicit"); the linear spline has none.
  static constexpr Real kInvD = Order == 2 ? Real(4) : Order == 3 ? Real(3) : Real(0);

  static int base_node(Real x) {
    if constexpr (Order == 1) return floor_int(x);
    else if constexpr (Order == 2) return floor_int(x - Real(0.5));
    else return floor_int(x) - 1;
  }

  explicit BSpline1D(Real x) {
    base = base_node(x);
    const Real fx = x - Real(base);  // linear [0,1), quadratic [0.5,1.5), cubic [1,2)
    if constexpr (Order == 1) {
      w[0] = 1 - fx, w[1] = fx;
      dw[0] = -1, dw[1] = 1;
      ddw[0] = ddw[1] = 0;
    } else if constexpr (Order == 2) {
      const Real a = Real(1.5) - fx, b = fx - 1, c = fx - Real(0.5);
      w[0] = Real(0.5) * a * a, w[1] = Real(0.75) - b * b, w[2] = Real(0.5) * c * c;
      dw[0] = -a, dw[1] = -2 * b, dw[2] = c;
      ddw[0] = 1, ddw[1] = -2, ddw[2] = 1;
    } else {
      for (int k = 0; k < kWidth; ++k) cubic(fx - Real(k), &w[k], &dw[k], &ddw[k]);
    }
  }

  // Cubic B-spline N(d) and its derivatives at signed distance d = x - x_node (grid units).
  static void cubic(Real d, Real* n, Real* dn, Real* ddn) {
    const Real s = d < 0 ? Real(-1) : Real(1), a = std::abs(d);
    if (a < 1) {
      *n = Real(0.5) * a * a * a - a * a + Real(2) / 3;
      *dn = s * (Real(1.5) * a * a - 2 * a);
      *ddn = 3 * a - 2;
    } else if (a < 2) {
      const Real t = 2 - a;
      *n = t * t * t / 6;
      *dn = -s * Real(0.5) * t * t;
      *ddn = t;
    } else {
      *n = *dn = *ddn = 0;
    }
  }
};

}  // namespace tear
