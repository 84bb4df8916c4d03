#include "tear/math/polar.h"
#include "tear/math/svd.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>

namespace tear {
namespace {

template <int Dim>
Mat<Dim> random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  if constexpr (Dim == 2) {
    const double t = std::atan2(n(rng), n(rng));
    Mat<2> Q;
    Q << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
    return Q;
  } else {
    return Eigen::Quaternion<Real>(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  }
}

// A family of deformation gradients U diag(sigma) V^T with random rotations U, V. The signed
// singular values are given largest first; a negative last one is an inverted F.
struct Spectra {
  const char* name;
  double lo, hi;  // |sigma| log-uniform in [lo, hi]
  double last;    // 0: like the others; else the last sigma is `last` times [0.5, 1.5]
  bool inverted;  // negate the last sigma (kept below 0.9 of the one before)
};

template <int Dim>
Vec<Dim> sample_sigma(const Spectra& f, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Vec<Dim> s;
  for (int i = 0; i < Dim; ++i) s[i] = Real(f.lo * std::pow(f.hi / f.lo, u(rng)));
  std::sort(s.data(), s.data() + Dim, [](Real x, Real y) { return x > y; });
  if (f.last != 0) s[Dim - 1] = Real(f.last * (0.5 + u(rng)));
  if (f.inverted) s[Dim - 1] = -std::min(s[Dim - 1], Real(0.9) * s[Dim - 2]);  // |s_d| < s_{d-1}
  return s;
}

const Spectra kFamilies[] = {
    {"mild", 0.7, 1.3, 0, false},           {"large_stretch", 0.05, 20, 0, false},
    {"near_singular", 0.5, 2, 1e-3, false}, {"nearer_singular", 0.5, 2, 1e-6, false},
    {"inverted", 0.3, 2, 0, true},          {"inverted_thin", 0.5, 2, 1e-3, true},
    {"rotation", 1, 1, 0, false},
};

// The fast rotation against the signed-SVD reference, family by family. The rotation is
// well conditioned in all of them (sigma_{d-1} + sigma_d >= 0.05 sigma_1 or so); the measured
// worst difference is ~2e-14, so 1e-12 leaves room for compilers.
template <int Dim>
void check_against_reference() {
  std::mt19937_64 rng(17 + Dim);
  int checked = 0;
  for (const Spectra& f : kFamilies) {
    double worst = 0, worst_orth = 0;
    for (int k = 0; k < 2000; ++k) {
      const Vec<Dim> sigma = sample_sigma<Dim>(f, rng);
      const Mat<Dim> F =
          random_rotation<Dim>(rng) * sigma.asDiagonal() * random_rotation<Dim>(rng).transpose();
      const Mat<Dim> R = polar_rotation<Dim>(F), ref = polar_rotation_svd<Dim>(F);
      worst = std::max(worst, double((R - ref).norm()));
      worst_orth = std::max(worst_orth, double((R.transpose() * R - Mat<Dim>::Identity()).norm()));
      EXPECT_NEAR(R.determinant(), 1, 1e-12) << f.name << " sigma " << sigma.transpose();
      ++checked;
    }
    EXPECT_LT(worst, 1e-12) << f.name;
    EXPECT_LT(worst_orth, 1e-12) << f.name;
  }
  EXPECT_EQ(checked, 2000 * int(std::size(kFamilies)));
}

TEST(Polar, MatchesTheSignedSvdReference2D) { check_against_reference<2>(); }
TEST(Polar, MatchesTheSignedSvdReference3D) { check_against_reference<3>(); }

// Independently of the SVD: R maximises tr(R^T F) over rotations (the rotation closest to F,
// inverted F included), so no nearby rotation R exp(W) does better.
template <int Dim>
void check_closest_rotation() {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 500; ++k) {
    Mat<Dim> F;
    for (int i = 0; i < Dim * Dim; ++i) F.data()[i] = Real(u(rng));
    const Mat<Dim> R = polar_rotation<Dim>(F);
    const Real best = (R.transpose() * F).trace();
    for (int t = 0; t < 8; ++t) {
      Mat<Dim> W = Mat<Dim>::Zero();  // a small rotation exp(W), W skew
      for (int i = 0; i < Dim; ++i)
        for (int j = i + 1; j < Dim; ++j) W(i, j) = -(W(j, i) = Real(1e-3 * u(rng)));
      const Mat<Dim> Q = R * (Mat<Dim>::Identity() + W + W * W / 2 + W * W * W / 6);
      EXPECT_LE((Q.transpose() * F).trace(), best + 1e-12);
    }
  }
}

TEST(Polar, IsTheClosestRotation2D) { check_closest_rotation<2>(); }
TEST(Polar, IsTheClosestRotation3D) { check_closest_rotation<3>(); }

TEST(Polar, ARotationIsItsOwnAndScaleDoesNotMatter) {
  std::mt19937_64 rng(3);
  for (int k = 0; k < 100; ++k) {
    const Mat<2> Q2 = random_rotation<2>(rng);
    const Mat<3> Q3 = random_rotation<3>(rng);
    EXPECT_LT((polar_rotation<2>(Q2) - Q2).norm(), 1e-14);
    EXPECT_LT((polar_rotation<3>(Q3) - Q3).norm(), 1e-14);
    Vec<3> s(1.2, 0.9, 0.7);
    const Mat<3> F = Q3 * s.asDiagonal() * random_rotation<3>(rng);
    const Mat<3> R = polar_rotation<3>(F);
    for (Real scale : {Real(1e-4), Real(1e4)})
      EXPECT_LT((polar_rotation<3>(scale * F) - R).norm(), 1e-14);
  }
}

// Inverted or collapsed 3D gradients, nearly rank-one ones and the 2D F = [a b; b -a] (no
// unique rotation) take the SVD: bit for bit the reference.
TEST(Polar, DegenerateCasesAreTheReference) {
  std::mt19937_64 rng(8);
  for (int k = 0; k < 50; ++k) {
    const Mat<3> U = random_rotation<3>(rng), V = random_rotation<3>(rng);
    for (const Vec<3>& s : {Vec<3>(1.5, 1, -0.5), Vec<3>(1, 1e-4, 1e-4)}) {
      const Mat<3> F = U * s.asDiagonal() * V.transpose();
      EXPECT_EQ(polar_rotation<3>(F), polar_rotation_svd<3>(F)) << s.transpose();
    }
    // Rank two (det F = 0 up to round-off, either sign): still a unique rotation.
    const Mat<3> F = U * Vec<3>(2, 1, 0).asDiagonal() * V.transpose();
    EXPECT_LT((polar_rotation<3>(F) - polar_rotation_svd<3>(F)).norm(), 1e-12);
  }
  Mat<2> G;
  G << 0.3, 0.7, 0.7, -0.3;
  EXPECT_EQ(polar_rotation<2>(G), polar_rotation_svd<2>(G));
  EXPECT_EQ(polar_rotation<3>(Mat<3>::Zero()), polar_rotation_svd<3>(Mat<3>::Zero()));
}

}  // namespace
}  // namespace tear
