// Cone (frustum, tapered tube), torus and wedge: the inside test against each shape's
// definition, and the signed distance shown exact — 1-Lipschitz (never more than the distance)
// and attained (stepping from p by -sdf along the normal lands on the surface) — at random
// points, in 2D and 3D, turned and moved; and a few values by hand.
#include "tear/geometry/shape.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <random>

namespace tear {
namespace {

constexpr double kPi = 3.14159265358979323846;

// p in the shape's own frame: along the axis (a), the distance from it (rho), and, for the
// wedge, the azimuth from `direction` about the axis.
struct Local {
  double a, rho, azimuth, r;
};
Local local(const Shape& s, const Vec3d& world) {
  Vec3d q = s.transform.to_local(world);
  if (s.dim == 2) q.z() = 0;
  const Vec3d axis = s.dim == 2 && s.type == Shape::Type::Wedge ? Vec3d::UnitZ() : s.axis;
  const Vec3d d = q - s.center;
  const double a = d.dot(axis);
  const Vec3d dir = (s.direction - s.direction.dot(axis) * axis).normalized();
  return {a, (d - a * axis).norm(), std::atan2(d.dot(axis.cross(dir)), d.dot(dir)), d.norm()};
}

// The definition of each shape, in world units (scale applied).
bool member(const Shape& s, const Vec3d& p) {
  const Local l = local(s, p);
  switch (s.type) {
    case Shape::Type::Cone: {
      if (std::abs(l.a) > 0.5 * s.height) return false;
      const double t = l.a / s.height + 0.5;
      const double outer = s.radius + t * (s.radius_top - s.radius);
      const double inner = s.inner_radius + t * (s.inner_radius_top - s.inner_radius);
      return l.rho <= outer && l.rho >= inner;
    }
    case Shape::Type::Torus:
      return std::hypot(l.rho - s.radius, l.a) <= s.tube_radius;
    case Shape::Type::Wedge:
      return l.r <= s.radius && l.r >= s.inner_radius && std::abs(l.azimuth) <= 0.5 * s.angle;
    default:
      return false;
  }
}

Shape make(Shape::Type type, int dim) {
  Shape s;
  s.type = type, s.dim = dim;
  s.center = Vec3d(0.1, -0.2, dim == 3 ? 0.3 : 0);
  s.axis = dim == 3 ? Vec3d(1, 2, 2) / 3 : Vec3d(0.6, 0.8, 0);
  return s;
}

// Inside test against the definition; exactness of the distance (see the file comment).
void expect_exact(const Shape& s, const std::string& what) {
  Vec3d lo, hi;
  s.bounds(&lo, &hi);
  const Vec3d mid = 0.5 * (lo + hi), half = 0.6 * (hi - lo);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  const double size = (hi - lo).maxCoeff();
  int inside = 0, attained = 0, n = 0;
  for (int k = 0; k < 3000; ++k) {
    Vec3d p = mid + half.cwiseProduct(Vec3d(u(rng), u(rng), u(rng)));
    if (s.dim == 2) p.z() = 0;
    const double d = s.sdf(p);
    // Bounds contain the shape.
    if (d <= 0) {
      EXPECT_TRUE(((p - lo).array() >= -1e-12).all() && ((hi - p).array() >= -1e-12).all())
          << what << " " << p.transpose();
    }
    EXPECT_EQ(s.inside(p), member(s, p)) << what << " " << p.transpose() << " sdf " << d;
    inside += member(s, p);
    // 1-Lipschitz: a small step changes the distance by at most its length.
    Vec3d step(u(rng), u(rng), u(rng));
    if (s.dim == 2) step.z() = 0;
    step *= 0.01 * size;
    EXPECT_LE(std::abs(s.sdf(p + step) - d), step.norm() * (1 + 1e-9) + 1e-12)
        << what << " " << p.transpose();
    // Attained: p - d n lies on the surface (except where n is not defined: kinks, seams).
    const Vec3d q = p - d * s.normal_at(p);
    ++n;
    attained += std::abs(s.sdf(q)) < 1e-6 * size;
  }
  EXPECT_GT(inside, 20) << what;
  EXPECT_GT(attained, n * 99 / 100) << what << ": " << attained << " of " << n;
}

TEST(RoundShapes, ConeFrustumAndTaperedTubeAreExact) {
  for (int dim : {2, 3}) {
    Shape cone = make(Shape::Type::Cone, dim);
    cone.height = 0.8, cone.radius = 0.3, cone.radius_top = 0.1;
    expect_exact(cone, "frustum " + std::to_string(dim) + "D");
    cone.radius_top = 1e-9;  // a pointed cone
    expect_exact(cone, "cone " + std::to_string(dim) + "D");
    Shape tube = make(Shape::Type::Cone, dim);
    tube.height = 0.8, tube.radius = 0.3, tube.radius_top = 0.15;
    tube.inner_radius = 0.2, tube.inner_radius_top = 0.05;
    tube.transform.scale = 1.5;
    tube.transform.translate = Vec3d(0.2, 0.1, 0);
    tube.transform.rotate = Eigen::AngleAxisd(0.4, Vec3d::UnitZ()).toRotationMatrix();
    expect_exact(tube, "tapered tube " + std::to_string(dim) + "D");
    tube.inner_radius = 0;  // hollow at the top only
    expect_exact(tube, "half-hollow " + std::to_string(dim) + "D");
  }
  // By hand: the frustum along z, radius 0.3 at z = -0.4, 0.1 at z = 0.4.
  Shape c;
  c.type = Shape::Type::Cone, c.axis = Vec3d::UnitZ(), c.height = 0.8;
  c.radius = 0.3, c.radius_top = 0.1;
  EXPECT_NEAR(c.sdf(Vec3d(0, 0, 0.5)), 0.1, 1e-15);   // above the top cap
  EXPECT_NEAR(c.sdf(Vec3d(0, 0, 0)), -0.2 / std::hypot(0.8, 0.2) * 0.8, 1e-12);  // side nearer
  EXPECT_NEAR(c.sdf(Vec3d(0.5, 0, -0.4)), 0.2, 1e-15);  // beside the bottom rim
  EXPECT_TRUE(c.inside(Vec3d(0.29, 0, -0.39)));
  EXPECT_FALSE(c.inside(Vec3d(0.21, 0, 0.39)));
}

TEST(RoundShapes, TorusIsExact) {
  for (int dim : {2, 3}) {
    Shape t = make(Shape::Type::Torus, dim);
    t.radius = 0.4, t.tube_radius = 0.15;
    expect_exact(t, "torus " + std::to_string(dim) + "D");
    t.transform.scale = 0.5;
    t.transform.rotate = Eigen::AngleAxisd(1.0, Vec3d::UnitZ()).toRotationMatrix();
    expect_exact(t, "moved torus " + std::to_string(dim) + "D");
  }
  Shape t;
  t.type = Shape::Type::Torus, t.axis = Vec3d::UnitZ(), t.radius = 1, t.tube_radius = 0.25;
  EXPECT_NEAR(t.sdf(Vec3d::Zero()), 0.75, 1e-15);  // the hole's centre
  EXPECT_NEAR(t.sdf(Vec3d(0, 1, 0)), -0.25, 1e-15);
  EXPECT_NEAR(t.sdf(Vec3d(0, -1, 0.5)), 0.25, 1e-15);
  Vec3d lo, hi;
  t.bounds(&lo, &hi);
  EXPECT_NEAR((hi - Vec3d(1.25, 1.25, 0.25)).norm(), 0, 1e-15);
}

TEST(RoundShapes, WedgeIsExact) {
  for (int dim : {2, 3}) {
    for (double deg : {30.0, 90.0, 150.0, 180.0}) {
      Shape w = make(Shape::Type::Wedge, dim);
      w.radius = 0.5, w.angle = deg * kPi / 180;
      w.direction = dim == 3 ? Vec3d(1, 0, 0) : Vec3d(-0.8, 0.6, 0);
      expect_exact(w, "wedge " + std::to_string(deg) + " " + std::to_string(dim) + "D");
      w.inner_radius = 0.35;  // the peel of an orange slice
      expect_exact(w, "shell wedge " + std::to_string(deg) + " " + std::to_string(dim) + "D");
    }
  }
  // By hand: a 90-degree wedge about z, towards +x, radius 1.
  Shape w;
  w.type = Shape::Type::Wedge, w.axis = Vec3d::UnitZ(), w.direction = Vec3d::UnitX();
  w.radius = 1, w.angle = kPi / 2;
  EXPECT_NEAR(w.sdf(Vec3d(0.5, 0, 0)), -0.5 * std::sqrt(0.5), 1e-15);  // nearer a face
  EXPECT_NEAR(w.sdf(Vec3d(-1, 0, 0)), 1, 1e-15);                       // behind the edge
  EXPECT_NEAR(w.sdf(Vec3d(0, 1, 0)), std::sqrt(0.5), 1e-15);           // beside a face
  EXPECT_NEAR(w.sdf(Vec3d(2, 0, 0)), 1, 1e-15);                        // beyond the rim
  EXPECT_TRUE(w.inside(Vec3d(0.7, 0.69, 0)));
  EXPECT_FALSE(w.inside(Vec3d(0.6, 0.61, 0)));
}

}  // namespace
}  // namespace tear
