#include "tear/grid/collider.h"
#include "tear/grid/sparse_grid.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>
#include <set>

namespace tear {
namespace {

template <int Dim>
std::vector<Vec<Dim>> random_points(int n, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<Dim>> x(n);
  for (auto& p : x)
    for (int d = 0; d < Dim; ++d) p[d] = Real(u(rng));
  return x;
}

template <int Dim>
void check_binning() {
  SparseGrid<Dim> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 64);
  auto x = random_points<Dim>(5000, 0.3, 0.6, 3);
  g.bin(x);
  // order() is a permutation grouped by home block, ascending inside each block.
  std::vector<int> seen(x.size(), 0);
  for (auto& h : g.home_blocks())
    for (uint32_t k = h.begin; k < h.end; ++k) {
      ++seen[g.order()[k]];
      EXPECT_EQ(g.particle_slot()[g.order()[k]], h.slot);
      if (k > h.begin) {
        EXPECT_LT(g.order()[k - 1], g.order()[k]);
      }
    }
  for (int s : seen) EXPECT_EQ(s, 1);
  // Every stencil node of every particle is active and maps back to its coordinates.
  for (const auto& p : x) {
    int visited = 0;
    Stencil<Dim, 3>(g, p).visit([&](int node, Real, const Vec<Dim>& rel) {
      ASSERT_GE(node, 0);
      const Vec<Dim> xi = g.node_position(node);
      EXPECT_TRUE((xi - p - rel).norm() < 1e-12);
      EXPECT_EQ(g.node_index(g.node_coord(node)), node);
      ++visited;
    });
    EXPECT_EQ(visited, (Stencil<Dim, 3>::kSize));
  }
  // Same-colour home blocks are at least two blocks apart on some axis.
  size_t total = 0;
  for (int c = 0; c < SparseGrid<Dim>::kColours; ++c) total += g.colour(c).size();
  EXPECT_EQ(total, g.home_blocks().size());
  // Memory follows the occupied region: far fewer nodes than the dense 65^Dim domain.
  EXPECT_LT(g.num_active_nodes(), size_t(std::pow(65.0, Dim)) / 2);
}

TEST(SparseGrid, BinningIsAStableGroupingAndStencilsAreActive2D) { check_binning<2>(); }
TEST(SparseGrid, BinningIsAStableGroupingAndStencilsAreActive3D) { check_binning<3>(); }

TEST(SparseGrid, StencilWeightsReproduceConstantsLinesAndTheMlsInertia) {
  SparseGrid<3> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 0.05);
  auto x = random_points<3>(100, 0.2, 0.8, 5);
  g.bin(x);
  for (const auto& p : x) {
    for (int order : {2, 3}) {
      double sw = 0, slap = 0;
      Vec<3> swx = Vec<3>::Zero();
      Mat<3> swxx = Mat<3>::Zero();
      auto add = [&](int, Real w, const Vec<3>& rel) {
        sw += w, swx += w * rel, swxx += w * rel * rel.transpose();
      };
      if (order == 2) {
        Stencil<3, 2>(g, p).visit(add);
      } else {
        const Stencil<3, 3> st(g, p);
        st.visit(add);
        st.visit_laplacian([&](int, Real lap_w) { slap += lap_w; });
        EXPECT_LT(std::abs(slap), 1e-9 / (0.05 * 0.05));  // Laplacian of a constant
      }
      EXPECT_NEAR(sw, 1, 1e-13);
      EXPECT_LT(swx.norm(), 1e-13);  // linear reproduction: sum w (x_i - x_p) = 0
      // sum w (x_i - x_p)(x_i - x_p)^T = dx^2 / kInvD I: the MLS-MPM inertia (4, resp. 3).
      const double inv_d = order == 2 ? 4 : 3;
      EXPECT_LT((swxx - Mat<3>::Identity() * (0.05 * 0.05 / inv_d)).norm(), 1e-15);
    }
  }
}

TEST(Boundary, StickyTakesTheWallVelocity) {
  const Vec<2> v(1, -2), vw(0.5, 0), n(0, 1);
  EXPECT_EQ(contact_velocity<2>(v, vw, n, ContactType::Sticky, 0), vw);
}

TEST(Boundary, SlipRemovesNormalRelativeVelocityBothWays) {
  const Vec<2> n(0, 1);
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, -2), Vec<2>::Zero(), n, ContactType::Slip, 0)
                  .isApprox(Vec<2>(1, 0)));
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, 2), Vec<2>::Zero(), n, ContactType::Slip, 0)
                  .isApprox(Vec<2>(1, 0)));
}

TEST(Boundary, SeparateOnlyStopsApproachAndFrictionSlowsTangent) {
  const Vec<2> n(0, 1);
  EXPECT_EQ(contact_velocity<2>(Vec<2>(1, 2), Vec<2>::Zero(), n, ContactType::Separate, 0.5),
            Vec<2>(1, 2));
  // |v_t| = 1, |v_n| = 1, mu = 0.5: tangential speed drops to 0.5.
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, -1), Vec<2>::Zero(), n, ContactType::Separate, 0.5)
                  .isApprox(Vec<2>(0.5, 0)));
  // mu large enough: the tangent stops.
  EXPECT_TRUE(contact_velocity<2>(Vec<2>(1, -1), Vec<2>::Zero(), n, ContactType::Separate, 2)
                  .isZero());
}

TEST(Boundary, ColliderMovesOnlyDuringItsWindow) {
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
  g.bin(random_points<2>(4000, 0.2, 0.8, 7));
  for (size_t i = 0; i < g.mass.size(); ++i) g.mass[i] = 1, g.velocity[i] = v;
  return g;
}

TEST(Boundary, SpinningStickyColliderImposesRigidVelocity) {
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

TEST(Boundary, HalfSpaceAndDomainWallsStopApproachingNodes) {
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

namespace tear {
namespace {

// The cubic-kernel Laplacian of a smooth field sampled on the grid nodes, evaluated at
// particles: exact for quadratics (the cubic B-spline reproduces them up to a constant
// shift, which the Laplacian removes) and second-order accurate for a cosine.
template <int Dim>
void check_laplacian() {
  std::vector<double> errors;
  for (double dx : {1.0 / 32, 1.0 / 64}) {
    SparseGrid<Dim> g;
    g.setup(Vec3d::Zero(), Vec3d::Ones(), dx);
    const auto x = random_points<Dim>(300, 0.3, 0.7, 11);
    g.bin(x);
    g.zero_scalar_fields();
    auto quadratic = [](const Vec<Dim>& p) { return 3 * p[0] * p[0] - p[0] * p[1] + 2 * p[1] * p[1]; };
    auto wave = [](const Vec<Dim>& p) { return std::cos(4 * p[0]) * std::cos(3 * p[1]); };
    for (int field = 0; field < 2; ++field) {
      for (size_t i = 0; i < g.scalar.size(); ++i) {
        const Vec<Dim> p = g.node_position(int(i));
        g.scalar[i] = field == 0 ? quadratic(p) : wave(p);
      }
      double worst = 0;
      for (const auto& p : x) {
        double lap = 0;
        Stencil<Dim, 3>(g, p).visit_laplacian(
            [&](int node, Real lap_w) { lap += lap_w * g.scalar[node]; });
        const double exact = field == 0 ? 10.0 : -25.0 * wave(p);
        worst = std::max(worst, std::abs(lap - exact));
      }
      if (field == 0) {
        EXPECT_LT(worst, 1e-8) << "quadratic, dx " << dx;
      } else {
        errors.push_back(worst);
      }
    }
  }
  // Halving dx divides the error by about 4.
  EXPECT_LT(errors[0], 0.1);  // 0.4% of max|Lap f| = 25 at dx = 1/32
  EXPECT_GT(errors[0] / errors[1], 3.0);
}

TEST(Stencil, CubicLaplacianIsExactForQuadraticsAndSecondOrder2D) { check_laplacian<2>(); }
TEST(Stencil, CubicLaplacianIsExactForQuadraticsAndSecondOrder3D) { check_laplacian<3>(); }

}  // namespace
}  // namespace tear
