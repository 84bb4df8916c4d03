// The shipped meshes of examples/meshes/ (tools/make_meshes.cpp, docs/meshes.md): each loads as
// a scene loads it (closed, 2-manifold, consistently oriented, nothing merged), fits the unit-ish
// box the docs promise, and tear's sampling (grid and random, 8 a cell) fills its exact volume
// to 3 %; the analytic ones lie on their formulas; flow fibers through the tapered tube run from
// the sources at its foot to the sinks at its top, unit, along the walls, with no divergence.
#include "scene_test_util.h"
#include "tear/geometry/mesh_solid.h"
#include "tear/io/mesh_io.h"
#include "tear/scene/flow_fibers.h"
#include "tear/scene/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace tear {
namespace {

using json = nlohmann::json;

const std::string kMeshDir = std::string(TEAR_SOURCE_DIR) + "/examples/meshes/";

struct Shipped {
  const char* name;
  double dx;  // sampling cell: the thinnest part (fins, ears, walls) a few cells across
};
const Shipped kShipped[] = {
    {"meat_slab", 0.0125}, {"orange_slice", 0.0125}, {"orange_pulp", 0.0125},
    {"fish", 0.01},        {"heart", 0.015},         {"femur", 0.01},
    {"armadillo", 0.0125}, {"tapered_tube", 0.0125}, {"torus", 0.0125}};

std::shared_ptr<const MeshSolid> load(const std::string& name, TriMesh* file = nullptr) {
  const TriMesh mesh = read_mesh_file(kMeshDir + name + ".obj");
  std::vector<Vec3d> v;
  for (const auto& p : mesh.vertices) v.push_back(p.cast<double>());
  if (file) *file = mesh;
  return std::make_shared<const MeshSolid>(v, mesh.triangles, name);
}

// A scene file beside the meshes (not written: parse_scene resolves "file" against its name)
// with the mesh as its one object, over the box [-0.5, 0.5]^3 every shipped mesh fits in.
Scene shipped_scene(const std::string& name, const std::string& sampling, double dx) {
  json doc = test::mesh_scene("meshes/" + name + ".obj", sampling, 8);
  doc["grid"] = {{"dx", dx}, {"domain_min", {-0.5, -0.5, -0.5}}, {"domain_max", {0.5, 0.5, 0.5}}};
  return parse_scene(doc, std::string(TEAR_SOURCE_DIR) + "/examples/shipped.json");
}

class ShippedMesh : public ::testing::TestWithParam<Shipped> {};

TEST_P(ShippedMesh, LoadsClosedAndSamplesToItsVolume) {
  const Shipped m = GetParam();
  TriMesh file;
  const std::shared_ptr<const MeshSolid> solid = load(m.name, &file);  // throws unless closed
  // Nothing merged or dropped, outward: the file is exactly the checked surface.
  EXPECT_EQ(solid->num_vertices(), file.vertices.size());
  EXPECT_EQ(solid->num_triangles(), file.triangles.size());
  EXPECT_FALSE(solid->turned_inside_out());
  EXPECT_LT(file.triangles.size(), 6000u);
  EXPECT_TRUE((solid->lo().array() > -0.45).all() && (solid->hi().array() < 0.45).all())
      << solid->lo().transpose() << " .. " << solid->hi().transpose();
  for (const std::string sampling : {"grid", "random"}) {
    const Scene s = shipped_scene(m.name, sampling, m.dx);
    const Particles<3> p = sample_scene<3>(s);
    double sampled = 0;
    for (size_t i = 0; i < p.size(); ++i) sampled += p.vol0[i];
    EXPECT_NEAR(sampled / solid->volume(), 1, 0.03) << sampling << ", " << p.size() << " particles";
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, ShippedMesh, ::testing::ValuesIn(kShipped),
                         [](const ::testing::TestParamInfo<Shipped>& i) { return i.param.name; });

TEST(ShippedMeshes, EveryFileIsTested) {
  std::vector<std::string> files, tested;
  for (const auto& e : std::filesystem::directory_iterator(kMeshDir))
    files.push_back(e.path().filename().string());
  for (const Shipped& m : kShipped) tested.push_back(std::string(m.name) + ".obj");
  std::sort(files.begin(), files.end());
  std::sort(tested.begin(), tested.end());
  EXPECT_EQ(files, tested);
}

TEST(ShippedMeshes, AnalyticOnesLieOnTheirFormulas) {
  // torus.obj: R 0.3, r 0.1 about z. Its vertices lie on the torus (OpenVDB puts them within a
  // fraction of the 0.006 voxel), and adaptive facets cut a little inside the curved surface.
  const std::shared_ptr<const MeshSolid> torus = load("torus");
  TriMesh t = read_mesh_file(kMeshDir + "torus.obj");
  double worst = 0;
  for (const auto& v : t.vertices)
    worst = std::max(worst, std::abs(std::hypot(std::hypot(v.x(), v.y()) - 0.3, v.z()) - 0.1));
  EXPECT_LT(worst, 2e-3);  // a third of a voxel
  const double exact = 2 * M_PI * M_PI * 0.3 * 0.1 * 0.1;
  EXPECT_LT(torus->volume(), exact);
  EXPECT_GT(torus->volume(), 0.96 * exact);
  // tapered_tube.obj: frusta of radii 0.2 -> 0.12 outside, 0.15 -> 0.07 inside, 0.6 tall; the
  // rims rounded by 0.01 take off a little.
  const double frustum = M_PI * 0.6 / 3 * ((0.04 + 0.024 + 0.0144) - (0.0225 + 0.0105 + 0.0049));
  const double tube = load("tapered_tube")->volume();
  EXPECT_LT(tube, frustum);
  EXPECT_GT(tube, 0.98 * frustum);
}

TEST(ShippedMeshes, OrangePulpAsARegionLeavesThePeelOnTheRoundSideOnly) {
  // The slice (radius 0.35) of "jelly" as the peel, the pulp (radius 0.31, past the cut faces)
  // as its region: the peel is the shell 0.31 < r <= 0.35 and nothing on the cut faces.
  json doc = test::mesh_scene("meshes/orange_slice.obj", "random", 8);
  doc["grid"] = {{"dx", 0.01}, {"domain_min", {-0.5, -0.5, -0.5}}, {"domain_max", {0.5, 0.5, 0.5}}};
  doc["materials"]["pulp"] = doc["materials"]["jelly"];
  doc["objects"][0]["regions"] = {
      {{"shape", {{"type", "mesh"}, {"file", "meshes/orange_pulp.obj"}}}, {"material", "pulp"}}};
  const Particles<3> p =
      sample_scene<3>(parse_scene(doc, std::string(TEAR_SOURCE_DIR) + "/examples/orange.json"));
  size_t peel = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const double r = p.x[i].cast<double>().norm();
    if (p.material[i] == 0) {  // materials in name order: jelly (the peel), pulp
      ++peel;
      ASSERT_GT(r, 0.305) << p.x[i].transpose();
    } else {
      ASSERT_LT(r, 0.315) << p.x[i].transpose();
    }
  }
  // The shell's share of the wedge, 1 - (0.31 / 0.35)^3, to the particles' spacing.
  EXPECT_NEAR(double(peel) / double(p.size()), 1 - std::pow(0.31 / 0.35, 3), 0.02);
}

TEST(ShippedMeshes, FlowFibersRunUpTheTaperedTube) {
  // Sources round the tube's foot, sinks round its top, on the walls' middle circles.
  Shape tube;
  tube.type = Shape::Type::Mesh;
  tube.mesh = load("tapered_tube");
  const MeshSolid& solid = *tube.mesh;
  const double h = 0.01, radius = 2 * h, zs = -0.28, zk = 0.28;
  auto mid_radius = [](double z) { return 0.135 - 0.08 / 0.6 * z; };  // between the walls
  std::vector<Vec3d> sources, sinks;
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * M_PI * k / 12;
    sources.emplace_back(mid_radius(zs) * std::cos(a), mid_radius(zs) * std::sin(a), zs);
    sinks.emplace_back(mid_radius(zk) * std::cos(a), mid_radius(zk) * std::sin(a), zk);
  }
  const FlowField flow(tube, 3, h, sources, sinks, radius);

  // Along the walls: unit, upwards along the wall's slant, tangent to its surfaces.
  const Vec3d slant = Vec3d(-0.08, 0, 0.6).normalized();  // up the wall, in the xz meridian
  int checked = 0, up = 0, near_surface = 0;
  double normal_sum = 0;
  for (double z = -0.2; z <= 0.2; z += 0.013)
    for (double a = 0; a < 2 * M_PI; a += 0.29)
      for (double off = -0.02; off <= 0.0201; off += 0.005) {
        const Vec3d radial(std::cos(a), std::sin(a), 0);
        const Vec3d p = (mid_radius(z) + off) * radial + Vec3d(0, 0, z);
        if (!solid.inside(p)) continue;
        const Vec3d f = flow.direction(p, Vec3d::Zero());
        ASSERT_NEAR(f.norm(), 1, 1e-12) << p.transpose();
        const Vec3d along = slant.x() * radial + slant.z() * Vec3d::UnitZ();
        ++checked;
        up += f.dot(along) > 0.95;
        if (solid.distance(p) < 1.5 * h)
          normal_sum += std::abs(f.dot(solid.normal(p))), ++near_surface;
      }
  EXPECT_GT(checked, 2000);
  EXPECT_GT(up, checked * 95 / 100) << up << " of " << checked;
  EXPECT_GT(near_surface, 500);
  EXPECT_LT(normal_sum / near_surface, 0.1);

  // No divergence: at every free cell (not held, with a potential) the potential differences
  // to its neighbours inside sum to zero (nothing flows out through the walls), so the flux up
  // through every level between the held rings is the same.
  Vec3d lo, hi;
  tube.bounds(&lo, &hi);
  lo -= Vec3d::Constant(h);  // the field's cells start a cell below the bounds
  const Eigen::Vector3i n = ((hi - lo) / h).array().ceil().cast<int>() + 1;
  auto centre = [&](int i, int j, int k) -> Vec3d {
    return lo + h * Vec3d(i + 0.5, j + 0.5, k + 0.5);
  };
  auto held = [&](const Vec3d& c) {
    for (const auto* points : {&sources, &sinks})
      for (const Vec3d& q : *points)
        if ((c - q).norm() <= radius) return true;
    return false;
  };
  double worst = 0, scale = 0;
  std::vector<double> flux(size_t(n.z()), 0.0);  // up through the top of layer k
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Vec3d c = centre(i, j, k);
        const double phi = flow.potential(c);
        if (std::isnan(phi)) continue;
        const double above = flow.potential(centre(i, j, k + 1));
        if (!std::isnan(above)) flux[size_t(k)] += phi - above;
        if (held(c)) continue;
        double balance = 0;
        for (int d = 0; d < 3; ++d)
          for (const int s : {-1, 1}) {
            const double nb = flow.potential(c + s * h * Vec3d::Unit(d));
            if (!std::isnan(nb)) balance += nb - phi, scale = std::max(scale, std::abs(nb - phi));
          }
        worst = std::max(worst, std::abs(balance));
      }
  EXPECT_GT(scale, 0);
  EXPECT_LT(worst, 1e-6 * scale);
  const double mid = flux[size_t((0.0 - lo.z()) / h)];
  EXPECT_GT(mid, 0);  // upwards, from the sources to the sinks
  for (double z = -0.24; z <= 0.24; z += 0.04)
    EXPECT_NEAR(flux[size_t((z - lo.z()) / h)], mid, 1e-5 * mid) << z;
}

}  // namespace
}  // namespace tear
