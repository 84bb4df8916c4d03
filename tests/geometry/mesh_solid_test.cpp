// Closed-mesh solids: the hierarchical winding number against the sum over every triangle, the
// inside test on a box, a torus (non-convex) and points on faces, edges and corners, distances,
// volumes, orientation, transforms through Shape, and every refusal with its reason.
#include "tear/geometry/mesh_solid.h"
#include "tear/geometry/shape.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

namespace tear {
namespace {

using test::box_mesh;
using test::TestMesh;
using test::torus_mesh;

constexpr double kPi = 3.14159265358979323846;

MeshSolid solid(const TestMesh& m) { return MeshSolid(m.vertices, m.triangles, "test mesh"); }

// The winding number as the plain sum over all triangles (no hierarchy).
double brute_winding(const TestMesh& m, const Vec3d& p) {
  double sum = 0;
  for (const auto& t : m.triangles) {
    const Vec3d a = m.vertices[size_t(t[0])] - p, b = m.vertices[size_t(t[1])] - p,
                c = m.vertices[size_t(t[2])] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    sum += 2 * std::atan2(a.dot(b.cross(c)),
                          la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return sum / (4 * kPi);
}

// Distance to the nearest of many points sampled on every triangle: an upper bound that the
// exact distance must not exceed, and approach closely.
double sampled_distance(const TestMesh& m, const Vec3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles)
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; i + j <= 20; ++j) {
        const Vec3d q = m.vertices[size_t(t[0])] +
                        (i / 20.0) * (m.vertices[size_t(t[1])] - m.vertices[size_t(t[0])]) +
                        (j / 20.0) * (m.vertices[size_t(t[2])] - m.vertices[size_t(t[0])]);
        best = std::min(best, (q - p).norm());
      }
  return best;
}

// Exact signed distance of the analytic torus about z (for points away from the mesh's chords).
double torus_sdf(const Vec3d& p, double R, double r) {
  return std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r;
}

TEST(MeshSolid, BoxInsideOutsideAndOnItsSurface) {
  const MeshSolid s = solid(box_mesh(Vec3d(0, 0, 0), Vec3d(1, 2, 3)));
  EXPECT_DOUBLE_EQ(s.volume(), 6);
  EXPECT_FALSE(s.turned_inside_out());
  EXPECT_EQ(s.lo(), Vec3d(0, 0, 0));
  EXPECT_EQ(s.hi(), Vec3d(1, 2, 3));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 3.5);
  int inside = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3d p(u(rng), u(rng), u(rng));
    const bool in = p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 2 && p.z() > 0 && p.z() < 3;
    inside += in;
    EXPECT_NEAR(s.winding_number(p), in ? 1.0 : 0.0, 1e-12) << p.transpose();
    EXPECT_EQ(s.inside(p), in) << p.transpose();
  }
  EXPECT_GT(inside, 120);  // 6 / 64 of the points
  // On the surface: faces (inside a triangle and on a face's diagonal), edges and corners are
  // all inside, at distance 0, as the analytic shapes' sdf <= 0 has it.
  for (const Vec3d& p : {Vec3d(0.5, 0, 1), Vec3d(0.5, 1, 0), Vec3d(1, 0.3, 2.9),
                         Vec3d(0.5, 2, 1.5), Vec3d(0.25, 0.5, 3), Vec3d(0, 1, 0),
                         Vec3d(1, 2, 1.5), Vec3d(0, 0, 0), Vec3d(1, 2, 3)}) {
    EXPECT_TRUE(s.inside(p)) << p.transpose();
    EXPECT_NEAR(s.distance(p), 0, 1e-15) << p.transpose();
    EXPECT_NEAR(s.signed_distance(p), 0, 1e-15) << p.transpose();
  }
  // Just off the surface, either way.
  EXPECT_TRUE(s.inside(Vec3d(0.5, 1e-9, 1)));
  EXPECT_FALSE(s.inside(Vec3d(0.5, -1e-9, 1)));
  EXPECT_NEAR(s.signed_distance(Vec3d(0.5, 1, 1.5)), -0.5, 1e-15);
  EXPECT_NEAR(s.signed_distance(Vec3d(2, 3, 4)), std::sqrt(3.0), 1e-15);
}

TEST(MeshSolid, HierarchyGivesTheSumOverEveryTriangle) {
  // A fine torus: thousands of triangles, so that most of the tree is summed through caps.
  const TestMesh m = torus_mesh(Vec3d(0.1, -0.2, 0.3), 1.0, 0.35, 64, 32);
  const MeshSolid s = solid(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 500; ++k) {
    const Vec3d p = Vec3d(0.1, -0.2, 0.3) + Vec3d(u(rng), u(rng), 0.5 * u(rng));
    const double w = s.winding_number(p);
    EXPECT_NEAR(w, brute_winding(m, p), 1e-10) << p.transpose();
    EXPECT_NEAR(w, std::round(w), 1e-10) << p.transpose();  // a closed surface: an integer
    EXPECT_EQ(s.inside(p), w >= 0.5) << p.transpose();        // the voxels' answer too
  }
}

TEST(MeshSolid, TorusIsNonConvexAndItsHoleIsOutside) {
  const double R = 1.0, r = 0.35;
  const MeshSolid s = solid(torus_mesh(Vec3d::Zero(), R, r, 48, 24));
  // The mesh's chords lie at most r (1 - cos(pi / 24)) + R (1 - cos(pi / 48)) inside the torus.
  const double chord = r * (1 - std::cos(kPi / 24)) + (R + r) * (1 - std::cos(kPi / 48));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int checked = 0, inside = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3d p(u(rng), u(rng), 0.4 * u(rng));
    const double d = torus_sdf(p, R, r);
    if (std::abs(d) < 2 * chord) continue;
    ++checked;
    inside += d < 0;
    EXPECT_EQ(s.inside(p), d < 0) << p.transpose();
  }
  EXPECT_GT(checked, 3000);
  EXPECT_GT(inside, 500);
  EXPECT_FALSE(s.inside(Vec3d::Zero()));        // the hole
  EXPECT_FALSE(s.inside(Vec3d(0, 0, 0.3)));     // above the hole
  EXPECT_TRUE(s.inside(Vec3d(-1, 0, 0.1)));     // in the ring
  EXPECT_NEAR(s.volume(), 2 * kPi * kPi * R * r * r, 0.02 * 2 * kPi * kPi * R * r * r);
}

TEST(MeshSolid, DistanceIsTheNearestPointOfAnyTriangle) {
  const TestMesh m = torus_mesh(Vec3d::Zero(), 1.0, 0.35, 24, 12);
  const MeshSolid s = solid(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.8, 1.8);
  for (int k = 0; k < 60; ++k) {
    const Vec3d p(u(rng), u(rng), 0.6 * u(rng));
    const double d = s.distance(p), sampled = sampled_distance(m, p);
    EXPECT_LE(d, sampled + 1e-12) << p.transpose();
    EXPECT_GT(d, sampled - 0.01) << p.transpose();  // samples 1/20 of an edge apart
    EXPECT_EQ(s.signed_distance(p), s.inside(p) ? -d : d);
  }
}

TEST(MeshSolid, InwardMeshIsTurnedAndSeparateVerticesAreMerged) {
  TestMesh m = box_mesh(Vec3d(0, 0, 0), Vec3d(1, 1, 1));
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const MeshSolid inward = solid(m);
  EXPECT_TRUE(inward.turned_inside_out());
  EXPECT_DOUBLE_EQ(inward.volume(), 1);
  EXPECT_TRUE(inward.inside(Vec3d(0.5, 0.5, 0.5)));
  EXPECT_NEAR(inward.winding_number(Vec3d(0.5, 0.5, 0.5)), 1, 1e-12);
  // As STL stores it: three vertices of its own per triangle.
  const TestMesh box = box_mesh(Vec3d(0, 0, 0), Vec3d(1, 1, 1));
  TestMesh soup;
  for (const auto& t : box.triangles) {
    const int n = int(soup.vertices.size());
    for (int v : t) soup.vertices.push_back(box.vertices[size_t(v)]);
    soup.triangles.push_back({n, n + 1, n + 2});
  }
  const MeshSolid merged = solid(soup);
  EXPECT_EQ(merged.num_vertices(), 8u);
  EXPECT_EQ(merged.num_triangles(), 12u);
  EXPECT_TRUE(merged.inside(Vec3d(0.5, 0.5, 0.5)));
  EXPECT_FALSE(merged.inside(Vec3d(1.5, 0.5, 0.5)));
}

TEST(MeshSolid, ThroughShapeWithATransform) {
  Shape s;
  s.type = Shape::Type::Mesh;
  s.mesh = std::make_shared<const MeshSolid>(solid(box_mesh(Vec3d(-1, -1, -1), Vec3d(1, 1, 1))));
  s.transform.scale = 0.5;
  s.transform.rotate = Eigen::AngleAxisd(kPi / 4, Vec3d::UnitZ()).toRotationMatrix();
  s.transform.translate = Vec3d(2, 0, 0);
  // The cube of half-width 0.5 about (2, 0, 0), turned 45 degrees about z: its corners in x
  // reach 2 +- 0.5 sqrt(2).
  EXPECT_TRUE(s.inside(Vec3d(2.7, 0, 0)));
  EXPECT_FALSE(s.inside(Vec3d(2.6, 0.6, 0)));
  EXPECT_FALSE(s.inside(Vec3d(2, 0, 0.6)));
  EXPECT_NEAR(s.sdf(Vec3d(2, 0, 0)), -0.5, 1e-12);
  EXPECT_NEAR(s.sdf(Vec3d(2, 0, 1.5)), 1.0, 1e-12);
  EXPECT_NEAR((s.normal_at(Vec3d(2, 0, 0.7)) - Vec3d::UnitZ()).norm(), 0, 1e-6);
  Vec3d lo, hi;
  s.bounds(&lo, &hi);
  EXPECT_NEAR(lo.x(), 2 - 0.5 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(hi.z(), 0.5, 1e-12);
  EXPECT_NEAR((s.world_center() - Vec3d(2, 0, 0)).norm(), 0, 1e-12);
}

TEST(MeshSolid, NormalsAndDistancesAgreeWithTheAnalyticBox) {
  // The same box as a mesh and as an analytic shape, both turned and moved: signed distances
  // and normals (closest point vs finite differences) agree away from the box's medial planes.
  Shape analytic;
  analytic.type = Shape::Type::Box;
  analytic.min = Vec3d(-0.3, -0.2, -0.1), analytic.max = Vec3d(0.3, 0.2, 0.1);
  analytic.transform.rotate = Eigen::AngleAxisd(0.7, Vec3d(1, 2, 3).normalized()).toRotationMatrix();
  analytic.transform.translate = Vec3d(0.5, 0.4, 0.3);
  analytic.transform.scale = 1.5;
  Shape mesh = analytic;
  mesh.type = Shape::Type::Mesh;
  mesh.mesh = std::make_shared<const MeshSolid>(solid(box_mesh(analytic.min, analytic.max)));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  int compared = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3d p = Vec3d(0.5, 0.4, 0.3) + Vec3d(u(rng), u(rng), u(rng));
    const Vec3d local = analytic.transform.to_local(p);
    // Inside, the nearest face is ambiguous on the medial planes |x| - 0.3 = |y| - 0.2, ...
    const Vec3d gap = Vec3d(0.3, 0.2, 0.1) - local.cwiseAbs();
    std::array<double, 3> g = {gap.x(), gap.y(), gap.z()};
    std::sort(g.begin(), g.end());
    if (analytic.sdf(p) < 0 && g[1] - g[0] < 1e-3) continue;
    ++compared;
    EXPECT_NEAR(mesh.sdf(p), analytic.sdf(p), 1e-12) << p.transpose();
    EXPECT_EQ(mesh.inside(p), analytic.inside(p)) << p.transpose();
    EXPECT_NEAR((mesh.normal_at(p) - analytic.normal_at(p)).norm(), 0, 1e-5) << p.transpose();
  }
  EXPECT_GT(compared, 2500);
}

// The message of building a solid from (vertices, triangles), or "" when it builds.
std::string refusal(const std::vector<Vec3d>& v, const std::vector<std::array<int, 3>>& t) {
  try {
    MeshSolid s(v, t);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(MeshSolid, RefusesWhatIsNotAClosedSolid) {
  const TestMesh box = box_mesh(Vec3d(0, 0, 0), Vec3d(1, 1, 1));
  EXPECT_EQ(refusal(box.vertices, box.triangles), "");
  EXPECT_EQ(refusal({}, {}), "has no triangles");
  EXPECT_EQ(refusal(box.vertices, {{0, 0, 1}}), "has no triangles of non-zero size");

  std::vector<Vec3d> nan = box.vertices;
  nan[3].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(nan, box.triangles).find("vertex 3 is not finite"), std::string::npos);

  std::vector<std::array<int, 3>> bad = box.triangles;
  bad[4][1] = 8;
  EXPECT_EQ(refusal(box.vertices, bad), "triangle 4 has vertex index 8, but there are 8 vertices");
  bad[4][1] = -1;
  EXPECT_NE(refusal(box.vertices, bad).find("vertex index -1"), std::string::npos);

  std::vector<std::array<int, 3>> open(box.triangles.begin(), box.triangles.end() - 1);
  const std::string why = refusal(box.vertices, open);
  EXPECT_EQ(why.rfind("is not closed: 3 edge(s) belong to one triangle only", 0), 0u) << why;

  std::vector<std::array<int, 3>> flipped = box.triangles;
  std::swap(flipped[5][1], flipped[5][2]);
  EXPECT_NE(refusal(box.vertices, flipped).find("is not consistently oriented: triangles"),
            std::string::npos);

  // A third triangle on an edge of the box.
  std::vector<Vec3d> fin = box.vertices;
  fin.emplace_back(0.5, -1, 0.5);
  std::vector<std::array<int, 3>> finned = box.triangles;
  finned.push_back({0, 1, 8});
  finned.push_back({1, 0, 8});
  EXPECT_NE(refusal(fin, finned).find("is not a manifold"), std::string::npos);

  // Closed and oriented but flat: a triangle and its back.
  EXPECT_EQ(refusal({Vec3d(0, 0, 0), Vec3d(1, 0, 0), Vec3d(0, 1, 0)}, {{0, 1, 2}, {0, 2, 1}}),
            "encloses no volume (it is flat or its parts cancel)");
}

TEST(MeshSolid, OverlappingShellsAreRefusedWhereTheyOverlap) {
  // Two boxes in one file that overlap: points in both wind twice.
  const TestMesh a = box_mesh(Vec3d(0, 0, 0), Vec3d(1, 1, 1));
  const TestMesh b = box_mesh(Vec3d(0.5, 0, 0), Vec3d(1.5, 1, 1));
  TestMesh both = a;
  for (const Vec3d& v : b.vertices) both.vertices.push_back(v);
  for (const auto& t : b.triangles) both.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  const MeshSolid s(both.vertices, both.triangles, "mesh 'two.obj'");
  EXPECT_TRUE(s.inside(Vec3d(0.25, 0.5, 0.5)));
  EXPECT_FALSE(s.inside(Vec3d(2, 0.5, 0.5)));
  try {
    s.inside(Vec3d(0.75, 0.5, 0.5));
    ADD_FAILURE() << "overlap accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh 'two.obj' winds 2 times around (0.75, 0.5, 0.5)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tear
