// The surface mesher: closed, manifold, outward meshes with the particles' volume; cracks that
// split a body; 2D slabs; the spacing estimate; the same bytes for any thread count; implicit
// solids (mesh_implicit).
#include "tear/surface/mesher.h"

#include <gtest/gtest.h>
#include "tear/exec/threads.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mesh_check.h"

namespace tear {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Points {
  std::vector<Eigen::Vector3d> p;
  std::vector<double> damage;
  void add(const Eigen::Vector3d& q, double d = 0) { p.push_back(q), damage.push_back(d); }

  // Columns as a run writes them (float32), z left out when `with_z` is false.
  PointTable table(bool with_z = true) const {
    PointTable t;
    t.count = p.size();
    std::vector<double> x, y, z;
    for (const Eigen::Vector3d& q : p) x.push_back(q.x()), y.push_back(q.y()), z.push_back(q.z());
    t.add("x", ColumnType::Float32, x);
    t.add("y", ColumnType::Float32, y);
    if (with_z) t.add("z", ColumnType::Float32, z);
    t.add("damage", ColumnType::Float32, damage);
    return t;
  }
};

// MPM sampling: lattice points at spacing h (shifted by `offset` lattice units) inside a ball.
Points lattice_ball(double h, double radius, const Eigen::Vector3d& centre,
                    const Eigen::Vector3d& offset) {
  Points b;
  const int n = int(std::ceil(radius / h)) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Eigen::Vector3d q = (Eigen::Vector3d(i, j, k) + offset) * h;
        if (q.norm() < radius) b.add(centre + q);
      }
  return b;
}

// A block of nx x ny x nz lattice points, rotated and shifted; layer k = nz / 2 has `damage`.
Points block(double h, int nx, int ny, int nz, const Eigen::Matrix3d& rotation,
             const Eigen::Vector3d& offset, double damage) {
  Points b;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        b.add(rotation * ((Eigen::Vector3d(i, j, k) + offset) * h), k == nz / 2 ? damage : 0.0);
  return b;
}

MeshOptions with_spacing(double h) {
  MeshOptions o;
  o.spacing = h;
  return o;
}

TEST(Spacing, EstimateIsTheLatticeSpacing) {
  const double h = 0.0125;
  const Points ball =
      lattice_ball(h, 8 * h, Eigen::Vector3d(0.3, 0.5, 0.2), Eigen::Vector3d(0.25, 0.5, 0.125));
  EXPECT_NEAR(estimate_spacing(ball.table()), h, 1e-6);  // float32 columns
  // 2D, no z column; and two far-apart clusters (the bounding box is mostly empty).
  Points plane;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 20; ++j) {
      plane.add(Eigen::Vector3d(i * 0.02, j * 0.02, 0));
      plane.add(Eigen::Vector3d(1000 + i * 0.02, j * 0.02, 0));
    }
  EXPECT_NEAR(estimate_spacing(plane.table(false)), 0.02, 1e-6);
  // Coincident points are left out; fewer than two distinct points give 0.
  Points one;
  one.add(Eigen::Vector3d(1, 2, 3));
  one.add(Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(estimate_spacing(one.table()), 0);
}

TEST(Mesher, LatticeBallIsClosedManifoldOutwardWithItsVolume) {
  const double h = 0.01, r = 10 * h;
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(0.1, 0.7, 0.35)}) {
    const Points ball = lattice_ball(h, r, Eigen::Vector3d(0.4, 0.3, 0.2), offset);
    const TriMesh mesh = mesh_particles(ball.table(), with_spacing(h));
    ASSERT_GT(mesh.triangles.size(), 1000u);
    const MeshCheck c = check_mesh(mesh);
    EXPECT_TRUE(c.closed);
    EXPECT_TRUE(c.oriented);
    EXPECT_TRUE(c.manifold);
    EXPECT_EQ(c.components, 1);
    const double exact = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_GT(c.volume, 0);  // counter-clockwise seen from outside
    EXPECT_NEAR(c.volume / exact, 1, 0.05) << c.volume << " vs " << exact;
  }
}

TEST(Mesher, OneDamagedLayerSplitsABlockInTwo) {
  const double h = 0.01;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 3; ++trial) {
    // Whatever the lattice's offset against the voxels, and turned (trial 2).
    const Eigen::Vector3d offset(u(rng), u(rng), u(rng));
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(trial == 2 ? 0.4 : 0.0, Eigen::Vector3d(1, 2, 3).normalized())
            .toRotationMatrix();
    const TriMesh cracked =
        mesh_particles(block(h, 10, 10, 11, turn, offset, 1.0).table(), with_spacing(h));
    const MeshCheck c = check_mesh(cracked);
    EXPECT_EQ(c.components, 2) << "trial " << trial;
    EXPECT_TRUE(c.closed && c.oriented && c.manifold) << "trial " << trial;
    const MeshCheck whole = check_mesh(
        mesh_particles(block(h, 10, 10, 11, turn, offset, 0.0).table(), with_spacing(h)));
    EXPECT_EQ(whole.components, 1) << "trial " << trial;
    EXPECT_TRUE(whole.closed && whole.oriented && whole.manifold) << "trial " << trial;
    EXPECT_NEAR(whole.volume / (1100 * h * h * h), 1, 0.05);
    EXPECT_LT(c.volume, whole.volume);
  }
}

TEST(Mesher, OneDamagedLayerSplitsAStratifiedRandomBallInTwo) {
  // The scenes' default sampling: one particle at a random place in each cell of the lattice.
  const double h = 0.01, r = 12 * h;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 2; ++trial) {
    Points ball;
    for (int i = -13; i < 13; ++i)
      for (int j = -13; j < 13; ++j)
        for (int k = -13; k < 13; ++k)
          if ((Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) * h).norm() < r)
            ball.add(Eigen::Vector3d(i + u(rng), j + u(rng), k + u(rng)) * h, k == 0 ? 1.0 : 0.0);
    const MeshCheck c = check_mesh(mesh_particles(ball.table(), with_spacing(h)));
    EXPECT_EQ(c.components, 2) << "trial " << trial;
    EXPECT_TRUE(c.closed && c.oriented && c.manifold) << "trial " << trial;
  }
}

TEST(Mesher, DamageAtOrBelowTheThresholdKeepsTheBodyWhole) {
  const double h = 0.01;
  const Points b = block(h, 8, 8, 9, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0.5);
  EXPECT_EQ(check_mesh(mesh_particles(b.table(), with_spacing(h))).components, 1);
  MeshOptions lower = with_spacing(h);
  lower.damage_threshold = 0.4;
  EXPECT_EQ(check_mesh(mesh_particles(b.table(), lower)).components, 2);
}

TEST(Mesher, FlatFrameMeshesAsAClosedSlabOneSpacingThick) {
  const double h = 0.01, r = 12 * h;
  Points disk;
  for (int i = -15; i <= 15; ++i)
    for (int j = -15; j <= 15; ++j) {
      const Eigen::Vector3d q((i + 0.5) * h, (j + 0.5) * h, 0.25);
      if (q.head<2>().norm() < r) disk.add(q);
    }
  const TriMesh mesh = mesh_particles(disk.table(), with_spacing(h));
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.closed && c.oriented && c.manifold);
  EXPECT_EQ(c.components, 1);
  float lo = 1e9f, hi = -1e9f;
  for (const Eigen::Vector3f& v : mesh.vertices) lo = std::min(lo, v.z()), hi = std::max(hi, v.z());
  EXPECT_NEAR(lo, 0.25 - h / 2, 0.15 * h);
  EXPECT_NEAR(hi, 0.25 + h / 2, 0.15 * h);
  EXPECT_NEAR(c.volume / (double(disk.p.size()) * h * h * h), 1, 0.1);
  // No z column: the same slab about z = 0.
  const TriMesh no_z = mesh_particles(disk.table(false), with_spacing(h));
  const MeshCheck cz = check_mesh(no_z);
  EXPECT_TRUE(cz.closed && cz.oriented && cz.manifold);
  EXPECT_NEAR(cz.volume, c.volume, 1e-3 * c.volume);
  lo = 1e9f, hi = -1e9f;
  for (const Eigen::Vector3f& v : no_z.vertices) lo = std::min(lo, v.z()), hi = std::max(hi, v.z());
  EXPECT_NEAR(lo, -h / 2, 0.15 * h);
  EXPECT_NEAR(hi, h / 2, 0.15 * h);
}

TEST(Mesher, SameBytesForOneAndTwoThreads) {
  // Jittered particles with scattered damage, so every step (carving included) runs.
  std::mt19937 rng(11);
  std::normal_distribution<double> jitter(0, 0.1);
  const double h = 0.01;
  Points b;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 16; ++k)
        b.add(Eigen::Vector3d(i + jitter(rng), j + jitter(rng), k + jitter(rng)) * h,
              i == 12 || (j + k) % 13 == 0 ? 0.9 : 0.0);
  const PointTable t = b.table();
  std::string one, two;
  {
    const ThreadLimit limit(1);
    one = encode_mesh_ply(mesh_particles(t, MeshOptions{}));
  }
  {
    const ThreadLimit limit(2);
    two = encode_mesh_ply(mesh_particles(t, MeshOptions{}));
  }
  EXPECT_GT(one.size(), 100000u);
  EXPECT_TRUE(one == two) << one.size() << " vs " << two.size() << " bytes";
}

TEST(Mesher, EmptyInputsGiveEmptyMeshesAndBadOptionsThrow) {
  EXPECT_TRUE(mesh_particles(Points{}.table(), MeshOptions{}).triangles.empty());
  const double h = 0.01;
  const Points all_damaged =
      block(h, 3, 3, 1, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1.0);
  EXPECT_TRUE(mesh_particles(all_damaged.table(), with_spacing(h)).triangles.empty());
  Points one;
  one.add(Eigen::Vector3d(0, 0, 0));
  EXPECT_THROW(mesh_particles(one.table(), MeshOptions{}), std::runtime_error);  // no spacing
  // A fragment of 3 x 3 x 3 particles is still a closed piece (a lone particle is finer than
  // the default voxels and smoothing: it vanishes).
  const MeshCheck fragment = check_mesh(mesh_particles(
      block(h, 3, 3, 3, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0.0).table(),
      with_spacing(h)));
  EXPECT_EQ(fragment.components, 1);
  EXPECT_TRUE(fragment.closed && fragment.oriented && fragment.manifold);
  MeshOptions bad = with_spacing(h);
  bad.voxel = 0.8;  // above radius / 1.5
  EXPECT_THROW(mesh_particles(one.table(), bad), std::invalid_argument);
  bad = with_spacing(-1);
  EXPECT_THROW(mesh_particles(one.table(), bad), std::invalid_argument);
  bad = with_spacing(h);
  bad.smooth = -2;
  EXPECT_THROW(mesh_particles(one.table(), bad), std::invalid_argument);
}

TEST(MeshImplicit, ABallAndARingAreClosedWithTheirVolumesAndTheSameBytesForAnyThreads) {
  // Two solids in one: a ball of radius 0.2 and, apart from it, a ring torus (R 0.15, r 0.05).
  // The torus's distance is exact; the ball's is scaled by 3 to show that only the sign and the
  // values near the surface matter.
  const Eigen::Vector3d c(0.25, 0, 0), t(-0.2, 0, 0);
  auto sdf = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - t;
    const double ring = std::hypot(std::hypot(q.x(), q.y()) - 0.15, q.z()) - 0.05;
    return std::min(3 * ((p - c).norm() - 0.2), ring);
  };
  const Eigen::Vector3d lo(-0.45, -0.25, -0.25), hi(0.5, 0.25, 0.25);
  for (const double adaptivity : {0.0, 0.3}) {
    SCOPED_TRACE(adaptivity);
    std::string bytes[2];
    TriMesh mesh;
    for (const int threads : {1, 2}) {
      const ThreadLimit limit(threads);
      mesh = mesh_implicit(sdf, lo, hi, 0.005, adaptivity);
      bytes[threads - 1] = encode_mesh_ply(mesh);
    }
    EXPECT_TRUE(bytes[0] == bytes[1]);
    const MeshCheck m = check_mesh(mesh);
    EXPECT_TRUE(m.closed && m.oriented && m.manifold);
    EXPECT_EQ(m.components, 2);
    const double exact = 4 * kPi / 3 * 0.008 + 2 * kPi * kPi * 0.15 * 0.0025;
    // Adaptive facets span several voxels and cut inside the curved surfaces a little more.
    EXPECT_NEAR(m.volume / exact, 1, 0.01 + 0.1 * adaptivity) << m.volume << " vs " << exact;
    for (const Eigen::Vector3f& v : mesh.vertices)  // on the surfaces, to a fraction of a voxel
      ASSERT_LT(std::abs(sdf(v.cast<double>())), 3 * 0.002) << v.transpose();
  }
  // The solid must not reach the box's sides (here the box cuts the ring); bad settings throw.
  EXPECT_THROW(mesh_implicit(sdf, Eigen::Vector3d(-0.1, -0.3, -0.3), hi, 0.01, 0),
               std::invalid_argument);
  EXPECT_THROW(mesh_implicit(sdf, lo, hi, 0, 0), std::invalid_argument);
  EXPECT_THROW(mesh_implicit(sdf, lo, hi, 0.01, 1.5), std::invalid_argument);
  EXPECT_THROW(mesh_implicit(sdf, hi, lo, 0.01, 0), std::invalid_argument);
}

}  // namespace
}  // namespace tear
