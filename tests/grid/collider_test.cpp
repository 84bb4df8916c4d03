// Colliders and domain walls acting on grid velocities (grid/collider.h).
#include "tear/grid/collider.h"
#include "tear/grid/sparse_grid.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace tear {
namespace {

std::vector<Vec<2>> random_points(int n, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<2>> x(n);
  for (auto& p : x)
    for (int d = 0; d < 2; ++d) p[d] = Real(u(rng));
  return x;
}

TEST(Collider, StickyTakesTheWallVelocity) {
  const Vec<2> v(1, -2), vw(0.5, 0), n(0, 1);
  EXPECT_EQ(contact_velocity<2>(v, vw, n, ContactType::Sticky, 0), vw);
}

TEST(Collider, SlipRemovesNormalRelativeVelocityBothWays) {
  const Vec<2> n(0, 1);
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, -2), Vec<2>::Zero(), n, ContactType::Slip, 0)
                  .isApprox(Vec<2>(1, 0)));
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, 2), Vec<2>::Zero(), n, ContactType::Slip, 0)
                  .isApprox(Vec<2>(1, 0)));
}

TEST(Collider, SeparateOnlyStopsApproachAndFrictionSlowsTangent) {
  const Vec<2> n(0, 1);
  EXPECT_EQ(contact_velocity<2>(Vec<2>(1, 2), Vec<2>::Zero(), n, ContactType::Separate, 0.5),
            Vec<2>(1, 2));
  // |v_t| = 1, |v_n| = 1, mu = 0.5: tangential speed drops to 0.5.
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, -1), Vec<2>::Zero(), n, ContactType::Separate, 0.5)
                  .isApprox(Vec<2>(0.5, 0)));
  // mu large enough: the tangent stops.
  EXPECT_TRUE(
      contact_velocity<2>(Vec<2>(1, -1), Vec<2>::Zero(), n, ContactType::Separate, 2).isZero());
}

TEST(Collider, ColliderMovesOnlyDuringItsWindow) {
  Collider b;
  b.velocity = Vec3d(1, 0, 0);
  b.start = 1, b.end = 2;
  EXPECT_FALSE(collider_state(b, 0.5).active);
  const ColliderState s = collider_state(b, 1.5);
  EXPECT_TRUE(s.active);
  EXPECT_TRUE(s.displacement.isApprox(Vec3d(0.5, 0, 0)));
  EXPECT_FALSE(collider_state(b, 2.5).active);
}

// Every active node of a grid over [0.2, 0.8]^2 with unit mass and velocity `v`.
SparseGrid<2> filled_grid(const Vec<2>& v) {
  SparseGrid<2> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 32);
  g.bin(random_points(4000, 0.2, 0.8, 7));
  for (size_t i = 0; i < g.mass.size(); ++i) g.mass[i] = 1, g.velocity[i] = v;
  return g;
}

TEST(Collider, SpinningStickyColliderImposesRigidVelocity) {
  SparseGrid<2> g = filled_grid(Vec<2>(3, 3));
  Collider b;
  b.type = ContactType::Sticky;
  b.shape.type = Shape::Type::Box;
  b.shape.dim = 2;
  b.shape.min = Vec3d(0.4, 0.4, 0);
  b.shape.max = Vec3d(0.6, 0.6, 0);
  b.velocity = Vec3d(0.1, 0, 0);
  b.angular_velocity = Vec3d(0, 0, 2);
  const double t = 0.25;  // moved by 0.025 and turned by 0.5 rad about its centre
  apply_colliders<2>(g, ContactType::None, {b}, t);
  const Vec3d centre(0.5 + 0.1 * t, 0.5, 0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5, Vec3d::UnitZ()).toRotationMatrix();
  int inside = 0, outside = 0;
  for (size_t i = 0; i < g.mass.size(); ++i) {
    const Vec<2> x = g.node_position(int(i));
    const Vec3d local = R.transpose() * (Vec3d(x[0], x[1], 0) - centre);
    const bool in = local.head<2>().cwiseAbs().maxCoeff() < 0.1 - 1e-9;
    const bool out = local.head<2>().cwiseAbs().maxCoeff() > 0.1 + 1e-9;
    if (in) {
      const Vec3d rigid = b.velocity + b.angular_velocity.cross(Vec3d(x[0], x[1], 0) - centre);
      EXPECT_LT((g.velocity[i] - rigid.head<2>()).norm(), 1e-12);
      ++inside;
    } else if (out) {
      EXPECT_EQ(g.velocity[i], Vec<2>(3, 3));
      ++outside;
    }
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 100);
}

// The placed shape (what pictures draw) is the collider where its motion puts it: in 2D a
// moving, spinning box; in 3D a transformed, moving, spinning cylinder. Its distance at a point
// is the rest shape's at the point moved back, and its inside is the collider's inside.
TEST(Collider, PlacedShapeIsTheShapeWhereTheMotionPutsIt) {
  Collider box;
  box.shape.type = Shape::Type::Box;
  box.shape.dim = 2;
  box.shape.min = Vec3d(0.4, 0.4, 0);
  box.shape.max = Vec3d(0.6, 0.6, 0);
  box.velocity = Vec3d(0.1, -0.2, 0);
  box.angular_velocity = Vec3d(0, 0, 2);
  box.start = 0.1;
  Collider cyl;
  cyl.shape.type = Shape::Type::Cylinder;
  cyl.shape.center = Vec3d(0.1, 0.2, -0.1);
  cyl.shape.axis = Vec3d(0, 0, 1);
  cyl.shape.radius = 0.1;
  cyl.shape.height = 0.3;
  cyl.shape.transform.translate = Vec3d(0.4, 0.3, 0.5);
  cyl.shape.transform.rotate =
      Eigen::AngleAxisd(0.7, Vec3d(1, 1, 0).normalized()).toRotationMatrix();
  cyl.shape.transform.scale = 1.5;
  cyl.velocity = Vec3d(0.3, 0, 0.1);
  cyl.angular_velocity = Vec3d(1, -2, 0.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (const Collider& c : {box, cyl}) {
    const double t = 0.35, elapsed = t - c.start;
    const ColliderState st = collider_state(c, t);
    const Shape placed = placed_shape(c, st);
    // The motion spelled out: translation by v (t - start), rotation by w (t - start) about the
    // shape's centre.
    const Vec3d centre = c.shape.world_center() + c.velocity * elapsed;
    const double w = c.angular_velocity.norm();
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(w * elapsed, c.angular_velocity / w).toRotationMatrix();
    EXPECT_LT((placed.world_center() - centre).norm(), 1e-12);
    int in = 0;
    for (int k = 0; k < 2000; ++k) {
      Vec3d p(u(rng), u(rng), c.shape.dim == 2 ? 0.0 : u(rng));
      const Vec3d rest = c.shape.world_center() + R.transpose() * (p - centre);
      EXPECT_NEAR(placed.sdf(p), c.shape.sdf(rest), 1e-12);
      EXPECT_EQ(placed.inside(p), c.shape.inside(rest));
      in += placed.inside(p);
    }
    EXPECT_GT(in, 10);
  }
}

TEST(Collider, HalfSpaceAndDomainWallsStopApproachingNodes) {
  SparseGrid<2> g = filled_grid(Vec<2>(0.5, -1));
  Collider floor;
  floor.type = ContactType::Separate;
  floor.friction = 0.25;
  floor.shape.type = Shape::Type::HalfSpace;
  floor.shape.dim = 2;
  floor.shape.point = Vec3d(0, 0.5, 0);
  floor.shape.normal = Vec3d(0, 1, 0);
  apply_colliders<2>(g, ContactType::Sticky, {floor}, 0);
  int wall = 0, below = 0, above = 0;
  for (size_t i = 0; i < g.mass.size(); ++i) {
    const Vec<2> x = g.node_position(int(i));
    const IVec<2> c = g.node_coord(int(i));
    if (c.minCoeff() < kWallNodes || c.maxCoeff() > g.num_nodes().maxCoeff() - 1 - kWallNodes) {
      EXPECT_TRUE(g.velocity[i].isZero());  // sticky domain wall
      ++wall;
    } else if (x[1] < 0.5 - 1e-9) {
      // Inside the floor: normal part removed, tangent reduced by friction * |v_n| = 0.25.
      EXPECT_LT((g.velocity[i] - Vec<2>(0.25, 0)).norm(), 1e-12) << g.velocity[i].transpose();
      ++below;
    } else if (x[1] > 0.5 + 1e-9) {
      EXPECT_EQ(g.velocity[i], Vec<2>(0.5, -1));
      ++above;
    }
  }
  EXPECT_GT(wall, 50);
  EXPECT_GT(below, 100);
  EXPECT_GT(above, 100);
}

}  // namespace
}  // namespace tear
