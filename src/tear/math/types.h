// math/: small dense kernels and the scalar/vector aliases every module uses.
// Owns: Real, Vec<Dim>, Mat<Dim>, TEAR_ASSERT. Knows nothing of particles, grids or scenes.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>  // determinant(), inverse()
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace tear {

#ifdef TEAR_FLOAT
using Real = float;
#else
using Real = double;
#endif

template <int Dim>
using Vec = Eigen::Matrix<Real, Dim, 1>;
template <int Dim>
using Mat = Eigen::Matrix<Real, Dim, Dim>;
template <int Dim>
using IVec = Eigen::Matrix<int, Dim, 1>;

using Vec3d = Eigen::Vector3d;  // scene-level geometry is always 3D double (z = 0 in 2D)

}  // namespace tear

#ifdef TEAR_ENABLE_ASSERTS
#define TEAR_ASSERT(cond)                                                                  \
  do {                                                                                     \
    if (!(cond)) {                                                                         \
      std::fprintf(stderr, "tear: internal check failed: %s (%s:%d)\n", #cond, __FILE__, \
                   __LINE__);                                                              \
      std::abort();                                                                        \
    }                                                                                      \
  } while (0)
#else
#define TEAR_ASSERT(cond) ((void)0)
#endif
