// math/: a few Reals side by side in one register (GCC/Clang vector extensions): lane-wise
// +, - and * (with a Real operand broadcast to every lane), each lane rounded as the scalar
// operation would be, so code over lanes gives the same bits as the same code over scalars.
// The compiler maps Lanes<4> of double to one AVX register or two SSE2 ones as the build
// allows, without Eigen's choice of packets for small fixed-size matrices (which, with AVX,
// stalls 2x2 work on store forwarding; CMakeLists.txt, TEAR_NATIVE).
//
// Made from N Reals (Lanes<4>{a, b, c, d}) or zero (Lanes<4>{}); lane-wise operations and
// subscripts only (lanes[i], also as an lvalue). Build lanes from scalars in one expression
// rather than lane by lane in memory: a vector read of lanes stored one by one waits on those
// stores (store-forwarding stall). Keep lanes in locals
// and arrays inside a function: passing a 32-byte vector by value or returning one changes the
// calling convention between builds with and without AVX (GCC's -Wpsabi warning).
#pragma once

#include "tear/math/types.h"

namespace tear {

template <int N>
struct LanesOf;
template <>
struct LanesOf<2> {
  typedef Real type __attribute__((vector_size(2 * sizeof(Real))));
};

#if defined(__AVX__) || defined(TEAR_LANES_AVX)
template <>
struct LanesOf<4> {
  typedef Real type __attribute__((vector_size(4 * sizeof(Real))));
};
#else
// Without AVX, four lanes as two pairs: GCC lowers a 32-byte vector type through the stack
// (store-forwarding stalls measured at a third of G2P), two 16-byte ones stay in registers.
struct Lanes4Pair {
  using Pair = typename LanesOf<2>::type;
  Pair lo, hi;
  Lanes4Pair() : lo{}, hi{} {}
  Lanes4Pair(Pair l, Pair h) : lo(l), hi(h) {}
  Lanes4Pair(Real a, Real b, Real c, Real d) : lo{a, b}, hi{c, d} {}
  Real& operator[](int i) { return i < 2 ? lo[i] : hi[i - 2]; }
  Real operator[](int i) const { return i < 2 ? lo[i] : hi[i - 2]; }
  Lanes4Pair& operator+=(const Lanes4Pair& o) {
    lo += o.lo, hi += o.hi;
    return *this;
  }
  friend Lanes4Pair operator+(Lanes4Pair a, const Lanes4Pair& b) { return a += b; }
  friend Lanes4Pair operator-(const Lanes4Pair& a, const Lanes4Pair& b) {
    return {a.lo - b.lo, a.hi - b.hi};
  }
  friend Lanes4Pair operator*(const Lanes4Pair& a, const Lanes4Pair& b) {
    return {a.lo * b.lo, a.hi * b.hi};
  }
  friend Lanes4Pair operator*(const Lanes4Pair& a, Real s) { return {a.lo * s, a.hi * s}; }
  friend Lanes4Pair operator*(Real s, const Lanes4Pair& a) { return {s * a.lo, s * a.hi}; }
};
template <>
struct LanesOf<4> {
  using type = Lanes4Pair;
};
#endif

// N Reals in lanes 0 .. N - 1 (N = 2 or 4).
template <int N>
using Lanes = typename LanesOf<N>::type;

}  // namespace tear
