// Crack figures on synthetic crack patterns with known answers: bands of a given width and
// angle in randomly sampled blocks (2D and 3D), several parallel bands, and the nearest-point
// distance between two crack sets.
#include "tear/damage/crack_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tear {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Stratified random points, `per_cell` per cell of size h, filling [0, size]^dim (z = 0 in 2D).
std::vector<Vec3d> random_block(int dim, double size, double spacing, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3d> x;
  const int n = int(size / spacing);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < (dim == 3 ? n : 1); ++k)
        x.emplace_back((i + u(rng)) * spacing, (j + u(rng)) * spacing,
                       dim == 3 ? (k + u(rng)) * spacing : 0.0);
  return x;
}

// Damage 1 within `width / 2` of the planes through `centres` with normal n, else 0.
std::vector<double> bands(const std::vector<Vec3d>& x, const Vec3d& n,
                          const std::vector<Vec3d>& centres, double width) {
  std::vector<double> d(x.size(), 0);
  for (size_t i = 0; i < x.size(); ++i)
    for (const Vec3d& c : centres)
      if (std::abs((x[i] - c).dot(n)) < width / 2) d[i] = 1;
  return d;
}

Vec3d line_normal(double degrees) {
  const double t = degrees * kPi / 180;
  return Vec3d(-std::sin(t), std::cos(t), 0);
}

TEST(CrackMetrics, OneBandIn2DAtAnyAngleAndWidth) {
  const double s = 0.01;
  const std::vector<Vec3d> x = random_block(2, 1, s, 3);
  for (double degrees : {-60.0, -45.0, 0.0, 30.0, 60.0, 89.0, 90.0})
    for (double w_spacings : {2.0, 4.0, 8.0}) {
      const std::vector<double> d =
          bands(x, line_normal(degrees), {Vec3d(0.5, 0.5, 0)}, w_spacings * s);
      const CrackFigures f = measure_cracks(2, x, d, s);
      EXPECT_NEAR(std::remainder(f.angle_degrees - degrees, 180.0), 0, 1.0)
          << degrees << " " << w_spacings;
      EXPECT_NEAR(f.width_spacings, w_spacings, 0.2 * w_spacings + 0.5)
          << degrees << " " << w_spacings;
    }
}

TEST(CrackMetrics, ParallelBandsWhereThePrincipalAxisPointsAcross) {
  // Three short bands at 60 degrees stacked along x: the cracked points as a whole spread
  // farthest along x, so their principal axis says about 0 degrees. The stripes say 60.
  const double s = 0.01;
  const std::vector<Vec3d> x = random_block(2, 1, s, 5);
  const Vec3d n = line_normal(60);
  std::vector<double> d(x.size(), 0);
  const Vec3d t(std::cos(kPi / 3), std::sin(kPi / 3), 0);
  for (size_t i = 0; i < x.size(); ++i)
    for (double cx : {0.2, 0.5, 0.8}) {
      const Vec3d r = x[i] - Vec3d(cx, 0.5, 0);
      if (std::abs(r.dot(n)) < 0.02 && std::abs(r.dot(t)) < 0.1) d[i] = 1;
    }
  const CrackFigures f = measure_cracks(2, x, d, s);
  EXPECT_NEAR(f.angle_degrees, 60, 1.5);
  EXPECT_NEAR(f.width_spacings, 4, 1.0);
  EXPECT_NEAR(f.fraction, double(f.cracked) / double(x.size()), 1e-15);
}

TEST(CrackMetrics, SlabsIn3D) {
  const double s = 0.04;
  const std::vector<Vec3d> x = random_block(3, 1, s, 7);
  for (const Vec3d& dir : {Vec3d(0, 1, 0), Vec3d(1, 1, 0), Vec3d(1, 2, 3)}) {
    const Vec3d n = dir.normalized();
    const std::vector<double> d = bands(x, n, {Vec3d(0.5, 0.5, 0.5)}, 4 * s);
    const CrackFigures f = measure_cracks(3, x, d, s);
    EXPECT_GT(std::abs(f.normal.dot(n)), std::cos(2 * kPi / 180)) << dir.transpose();
    EXPECT_NEAR(f.width_spacings, 4, 1.0) << dir.transpose();
  }
}

TEST(CrackMetrics, NothingCracked) {
  const std::vector<Vec3d> x = random_block(2, 0.2, 0.01, 1);
  const CrackFigures f = measure_cracks(2, x, std::vector<double>(x.size(), 0.5), 0.01);
  EXPECT_EQ(f.cracked, 0u);  // exactly at the threshold is not cracked
  EXPECT_EQ(f.width, 0);
  EXPECT_EQ(f.normal, Vec3d::Zero());
}

TEST(CrackMetrics, MeanNearestDistance) {
  const std::vector<Vec3d> a = random_block(2, 0.3, 0.01, 2);
  EXPECT_EQ(mean_nearest_distance(a, a), 0);
  std::vector<Vec3d> b = a;
  for (Vec3d& p : b) p += Vec3d(0, 0, 0.004);  // every point's nearest is its own copy
  EXPECT_NEAR(mean_nearest_distance(a, b), 0.004, 1e-12);
  EXPECT_TRUE(std::isinf(mean_nearest_distance(a, {})));
  EXPECT_EQ(mean_nearest_distance({}, {}), 0);
}

}  // namespace
}  // namespace tear
