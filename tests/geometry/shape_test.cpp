// Signed distances, normals, bounds and centres of analytic shapes at known points.
#include "tear/geometry/shape.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

namespace tear {
namespace {

constexpr double kPi = 3.14159265358979323846;

Shape box(int dim, Vec3d lo, Vec3d hi) {
  Shape s;
  s.type = Shape::Type::Box, s.dim = dim, s.min = lo, s.max = hi;
  return s;
}

Shape round_shape(Shape::Type type, int dim, Vec3d c, Vec3d axis, double r, double ri, double h) {
  Shape s;
  s.type = type, s.dim = dim, s.center = c, s.axis = axis;
  s.radius = r, s.inner_radius = ri, s.height = h;
  return s;
}

TEST(ShapeSdf, Box) {
  Shape b2 = box(2, Vec3d(0, 0, 0), Vec3d(2, 1, 0));
  EXPECT_DOUBLE_EQ(b2.sdf(Vec3d(1, 0.5, 0)), -0.5);
  EXPECT_DOUBLE_EQ(b2.sdf(Vec3d(1, 0.5, 7)), -0.5);  // z ignored in 2D
  EXPECT_DOUBLE_EQ(b2.sdf(Vec3d(3, 0.5, 0)), 1);
  EXPECT_DOUBLE_EQ(b2.sdf(Vec3d(3, 2, 0)), std::sqrt(2.0));
  EXPECT_TRUE(b2.inside(Vec3d(0.1, 0.9, 0)));
  Shape b3 = box(3, Vec3d(0, 0, 0), Vec3d(2, 1, 1));
  EXPECT_DOUBLE_EQ(b3.sdf(Vec3d(1, 0.5, 0.5)), -0.5);
  EXPECT_DOUBLE_EQ(b3.sdf(Vec3d(1, 0.5, 2)), 1);
  EXPECT_DOUBLE_EQ(b3.sdf(Vec3d(3, 2, 1)), std::sqrt(2.0));
  EXPECT_NEAR((b3.normal_at(Vec3d(1, 0.5, 1.2)) - Vec3d::UnitZ()).norm(), 0, 1e-6);
}

TEST(ShapeSdf, SphereAndDisk) {
  Shape s3 = round_shape(Shape::Type::Sphere, 3, Vec3d::Zero(), Vec3d::UnitX(), 1, 0, 0);
  EXPECT_DOUBLE_EQ(s3.sdf(Vec3d(2, 0, 0)), 1);
  EXPECT_DOUBLE_EQ(s3.sdf(Vec3d(0, 0, 0.25)), -0.75);
  EXPECT_NEAR((s3.normal_at(Vec3d(0, 2, 0)) - Vec3d::UnitY()).norm(), 0, 1e-6);
  Shape d2 = round_shape(Shape::Type::Sphere, 2, Vec3d(1, 1, 0), Vec3d::UnitX(), 1, 0, 0);
  EXPECT_DOUBLE_EQ(d2.sdf(Vec3d(1, 1.5, 0)), -0.5);
  EXPECT_DOUBLE_EQ(d2.sdf(Vec3d(1, 1, 5)), -1);  // a disk, not a ball
  EXPECT_DOUBLE_EQ(d2.sdf(Vec3d(4, 5, 0)), 4);
}

TEST(ShapeSdf, Cylinder) {
  Shape c3 = round_shape(Shape::Type::Cylinder, 3, Vec3d::Zero(), Vec3d(0, 0, 2), 1, 0, 2);
  EXPECT_DOUBLE_EQ(c3.sdf(Vec3d(0, 0, 0)), -1);
  EXPECT_DOUBLE_EQ(c3.sdf(Vec3d(0.5, 0, 0.9)), -0.1);
  EXPECT_DOUBLE_EQ(c3.sdf(Vec3d(2, 0, 0)), 1);
  EXPECT_DOUBLE_EQ(c3.sdf(Vec3d(0, 0, 3)), 2);
  EXPECT_DOUBLE_EQ(c3.sdf(Vec3d(0, 2, 2)), std::sqrt(2.0));
  // 2D: a 4 x 1 rectangle along x.
  Shape c2 = round_shape(Shape::Type::Cylinder, 2, Vec3d::Zero(), Vec3d(1, 0, 0), 0.5, 0, 4);
  EXPECT_DOUBLE_EQ(c2.sdf(Vec3d(0, 0, 0)), -0.5);
  EXPECT_DOUBLE_EQ(c2.sdf(Vec3d(3, 0, 0)), 1);
  EXPECT_DOUBLE_EQ(c2.sdf(Vec3d(0, 1, 0)), 0.5);
  EXPECT_NEAR(c2.sdf(Vec3d(1.9, -0.3, 0)), -0.1, 1e-12);
  Vec3d lo, hi;
  c2.bounds(&lo, &hi);
  EXPECT_TRUE(lo.isApprox(Vec3d(-2, -0.5, 0)));
  EXPECT_TRUE(hi.isApprox(Vec3d(2, 0.5, 0)));
}

TEST(ShapeSdf, Tube) {
  Shape t3 = round_shape(Shape::Type::Tube, 3, Vec3d::Zero(), Vec3d::UnitZ(), 1, 0.5, 2);
  EXPECT_DOUBLE_EQ(t3.sdf(Vec3d(0, 0, 0)), 0.5);  // in the hole
  EXPECT_DOUBLE_EQ(t3.sdf(Vec3d(0.75, 0, 0)), -0.25);
  EXPECT_DOUBLE_EQ(t3.sdf(Vec3d(0, -0.75, 0.5)), -0.25);
  EXPECT_DOUBLE_EQ(t3.sdf(Vec3d(2, 0, 0)), 1);
  EXPECT_DOUBLE_EQ(t3.sdf(Vec3d(0.75, 0, 1.5)), 0.5);
  EXPECT_NEAR((t3.normal_at(Vec3d(0.2, 0, 0)) - Vec3d(-1, 0, 0)).norm(), 0, 1e-6);
  // 2D: two strips 0.5 <= |x| <= 1, |y| <= 1.
  Shape t2 = round_shape(Shape::Type::Tube, 2, Vec3d::Zero(), Vec3d::UnitY(), 1, 0.5, 2);
  EXPECT_DOUBLE_EQ(t2.sdf(Vec3d(0.75, 0, 0)), -0.25);
  EXPECT_DOUBLE_EQ(t2.sdf(Vec3d(-0.75, 0.5, 0)), -0.25);
  EXPECT_DOUBLE_EQ(t2.sdf(Vec3d(0, 0, 0)), 0.5);
  EXPECT_DOUBLE_EQ(t2.sdf(Vec3d(0.75, 2, 0)), 1);
}

TEST(ShapeSdf, HalfSpace) {
  Shape h;
  h.type = Shape::Type::HalfSpace, h.dim = 3, h.point = Vec3d(0, 1, 0), h.normal = Vec3d(0, 2, 0);
  EXPECT_DOUBLE_EQ(h.sdf(Vec3d(0, 0, 0)), -1);
  EXPECT_DOUBLE_EQ(h.sdf(Vec3d(5, 3, -4)), 2);
  EXPECT_TRUE(h.normal_at(Vec3d(0, 0, 0)).isApprox(Vec3d::UnitY()));
  Vec3d lo, hi;
  h.bounds(&lo, &hi);
  EXPECT_TRUE(std::isinf(lo.x()) && lo.x() < 0 && std::isinf(hi.y()));
  h.dim = 2, h.normal = Vec3d(1, 1, 0);
  EXPECT_NEAR(h.sdf(Vec3d(1, 1, 0)), 1 / std::sqrt(2.0), 1e-15);
}

TEST(ShapeSdf, TransformedBox2D) {
  // [-1,1] x [-0.5,0.5], scaled 2, rotated 90 degrees, moved to (5,0): [4,6] x [-2,2].
  Shape b = box(2, Vec3d(-1, -0.5, 0), Vec3d(1, 0.5, 0));
  b.transform.scale = 2;
  b.transform.rotate = Eigen::AngleAxisd(kPi / 2, Vec3d::UnitZ()).toRotationMatrix();
  b.transform.translate = Vec3d(5, 0, 0);
  EXPECT_NEAR(b.sdf(Vec3d(5, 0, 0)), -1, 1e-12);
  EXPECT_NEAR(b.sdf(Vec3d(5, 3, 0)), 1, 1e-12);
  EXPECT_NEAR(b.sdf(Vec3d(7, 0, 0)), 1, 1e-12);
  EXPECT_NEAR((b.normal_at(Vec3d(5, 2.5, 0)) - Vec3d::UnitY()).norm(), 0, 1e-6);
  Vec3d lo, hi;
  b.bounds(&lo, &hi);
  EXPECT_TRUE(lo.isApprox(Vec3d(4, -2, 0), 1e-12));
  EXPECT_TRUE(hi.isApprox(Vec3d(6, 2, 0), 1e-12));
  EXPECT_TRUE(b.world_center().isApprox(Vec3d(5, 0, 0)));
}

TEST(ShapeSdf, TransformedCylinder3D) {
  // Axis z turned 90 degrees about x becomes -y; centre moved to (1, 2, 3).
  Shape c = round_shape(Shape::Type::Cylinder, 3, Vec3d::Zero(), Vec3d::UnitZ(), 0.5, 0, 2);
  c.transform.rotate = Eigen::AngleAxisd(kPi / 2, Vec3d::UnitX()).toRotationMatrix();
  c.transform.translate = Vec3d(1, 2, 3);
  EXPECT_NEAR(c.sdf(Vec3d(1, 3.5, 3)), 0.5, 1e-12);
  EXPECT_NEAR(c.sdf(Vec3d(1, 2.9, 3)), -0.1, 1e-12);
  EXPECT_NEAR(c.sdf(Vec3d(2, 2, 3)), 0.5, 1e-12);
  EXPECT_NEAR((c.normal_at(Vec3d(1, 3.5, 3)) - Vec3d::UnitY()).norm(), 0, 1e-6);
  Vec3d lo, hi;
  c.bounds(&lo, &hi);
  EXPECT_TRUE(lo.isApprox(Vec3d(0.5, 1, 2.5), 1e-12));
  EXPECT_TRUE(hi.isApprox(Vec3d(1.5, 3, 3.5), 1e-12));
  EXPECT_TRUE(c.world_center().isApprox(Vec3d(1, 2, 3)));
}

TEST(ShapeSdf, ScaledSphereKeepsWorldDistances) {
  Shape s = round_shape(Shape::Type::Sphere, 3, Vec3d::Zero(), Vec3d::UnitX(), 1, 0, 0);
  s.transform.scale = 3;
  EXPECT_NEAR(s.sdf(Vec3d(5, 0, 0)), 2, 1e-12);
  EXPECT_NEAR(s.sdf(Vec3d(0, 0, 0)), -3, 1e-12);
}

}  // namespace
}  // namespace tear
