// Test helper of tests/grid/: n points uniform in [lo, hi)^Dim from a seed.
#pragma once

#include "tear/math/types.h"

#include <random>
#include <vector>

namespace tear {

template <int Dim>
std::vector<Vec<Dim>> random_points(int n, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<Dim>> x(n);
  for (auto& p : x)
    for (int d = 0; d < Dim; ++d) p[d] = Real(u(rng));
  return x;
}

}  // namespace tear
