// FEM bodies from volume mesh files ("shape": {"type": "mesh", "file": X.msh | X.node | X.vtu}):
// every format gives the file's elements, placed by the shape's transform; a file of elements
// all the other way round is turned; bad files are refused naming the field, the file, the
// element and the reason; the same file as an MPM object samples the solid it fills.
#include "tear/driver/simulation.h"
#include "tear/io/volume_mesh.h"
#include "tear/scene/scene.h"
#include "fem_test_util.h"
#include "../scene/scene_test_util.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace tear {
namespace {

using test::structured_box;

// gmsh MSH 4.1 ASCII: one node block and one element block (tetrahedra, or triangles in 2D).
std::string gmsh_text(const FemMesh& m) {
  std::ostringstream o;
  o.precision(17);
  const size_t n = m.nodes.size(), e = m.elements.size();
  o << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 " << n << " 1 " << n << "\n"
    << m.dim << " 1 0 " << n << "\n";
  for (size_t i = 0; i < n; ++i) o << i + 1 << "\n";
  for (const Vec3d& x : m.nodes) o << x.x() << " " << x.y() << " " << x.z() << "\n";
  o << "$EndNodes\n$Elements\n1 " << e << " 1 " << e << "\n"
    << m.dim << " 1 " << (m.dim == 3 ? 4 : 2) << " " << e << "\n";
  for (size_t k = 0; k < e; ++k) {
    o << k + 1;
    for (int c = 0; c < m.corners(); ++c) o << " " << m.elements[k][size_t(c)] + 1;
    o << "\n";
  }
  o << "$EndElements\n";
  return o.str();
}

// TetGen's (Triangle's in 2D) .node and .ele, numbered from 1.
std::pair<std::string, std::string> tetgen_text(const FemMesh& m) {
  std::ostringstream node, ele;
  node.precision(17);
  node << m.nodes.size() << " " << m.dim << " 0 0\n";
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    node << i + 1 << " " << m.nodes[i].x() << " " << m.nodes[i].y();
    if (m.dim == 3) node << " " << m.nodes[i].z();
    node << "\n";
  }
  ele << m.elements.size() << " " << m.corners() << " 0\n";
  for (size_t k = 0; k < m.elements.size(); ++k) {
    ele << k + 1;
    for (int c = 0; c < m.corners(); ++c) ele << " " << m.elements[k][size_t(c)] + 1;
    ele << "\n";
  }
  return {node.str(), ele.str()};
}

std::string vtu_bytes(const FemMesh& m) {
  VolumeMesh v;
  v.dim = m.dim;
  for (const Vec3d& x : m.nodes) v.nodes.push_back({x.x(), x.y(), x.z()});
  for (const std::array<int, 4>& t : m.elements)
    v.cells.push_back({uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2]),
                       m.dim == 3 ? uint32_t(t[3]) : 0u});
  return encode_volume_vtu(v);
}

// A scene of one object with the given shape (and extra object keys), dim 2 or 3.
std::string scene_text(int dim, const std::string& shape, const std::string& extra = "",
                       bool fem = true) {
  const std::string lo = dim == 3 ? "[-1, -1, -1]" : "[-1, -1]", hi = dim == 3 ? "[2, 2, 2]" : "[2, 2]";
  return R"({"dim": )" + std::to_string(dim) + R"(, "grid": {"dx": 0.05, "domain_min": )" + lo +
         R"(, "domain_max": )" + hi + R"(, "walls": "none"},
      "time": {"frame_dt": 0.01, "frames": 1},
      "materials": {"m": {"model": "fixed_corotated", "E": 1e4, "nu": 0.3, "rho": 1000}},
      "objects": [{)" + (fem ? R"("simulation": "fem", )" : "") + R"("material": "m", "shape": )" +
         shape + extra + "}]}";
}

std::string scene_error(const std::string& text) {
  try {
    load_scene_text(text, test::write_temp("fem_mesh_file_scene.json", ""));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

// The file's nodes, turned 30 degrees about z, scaled by 2 and moved: the body's nodes exactly;
// its elements the file's (their count, their volume times 2^dim).
TEST(FemMeshFiles, EveryFormatGivesTheFileElementsPlacedByTheTransform) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const double z = dim == 3 ? 1 : 0;
    const FemMesh mesh = structured_box(dim, Vec3d(0.1, 0.2, 0.1 * z), Vec3d(0.4, 0.3, 0.3 * z), {3, 2, 2});
    const MeshFigures file = mesh_figures(mesh);
    const std::string stem = "fem_file_" + std::to_string(dim) + "d";
    const auto [node, ele] = tetgen_text(mesh);
    test::write_temp(stem + ".ele", ele);
    const std::vector<std::string> files = {test::write_temp(stem + ".msh", gmsh_text(mesh)),
                                            test::write_temp(stem + ".node", node),
                                            test::write_temp(stem + ".vtu", vtu_bytes(mesh))};
    const std::string rotate = dim == 3 ? R"({"axis": [0, 0, 1], "angle_deg": 30})" : "30";
    const std::string translate = dim == 3 ? "[0.2, 0.1, 0.3]" : "[0.2, 0.1]";
    const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Vec3d t(0.2, 0.1, dim == 3 ? 0.3 : 0);
    for (const std::string& f : files) {
      SCOPED_TRACE(f);
      const std::string shape = R"({"type": "mesh", "file": ")" + f + R"(", "transform": {"translate": )" +
                                translate + R"(, "rotate": )" + rotate + R"(, "scale": 2}})";
      const Scene scene = load_scene_text(scene_text(dim, shape), test::write_temp("fem_file.json", ""));
      ASSERT_TRUE(scene.objects[0].fem_mesh);
      auto sim = make_simulation(scene);
      ASSERT_EQ(sim->num_particles(), mesh.nodes.size());
      const MeshFigures body = sim->body_meshes().at(0);
      EXPECT_EQ(body.elements, mesh.elements.size());
      EXPECT_NEAR(body.volume, file.volume * std::pow(2.0, dim), 1e-12);
      EXPECT_NEAR(body.mean_edge, 2 * file.mean_edge, 1e-12);
      EXPECT_NEAR(scene.objects[0].mesh_size, 2 * file.mean_edge, 1e-12);
      const PointTable& table = sim->frame_table();
      double worst = 0;
      for (size_t i = 0; i < mesh.nodes.size(); ++i) {
        const Vec3d want = t + R * (2 * mesh.nodes[i]);
        Vec3d got(table.column("x")[i], table.column("y")[i], dim == 3 ? table.column("z")[i] : 0.0);
        worst = std::max(worst, (got - want).norm());
      }
      EXPECT_LT(worst, 1e-12);
      // The run steps: the body falls freely under gravity, unstrained.
      sim->advance_frame();
      EXPECT_LT(sim->collect_stats().elastic_energy, 1e-9);
    }
  }
}

// Triangles listed clockwise throughout (another program's convention) are turned; a mix of
// orientations is refused at the first inverted element, as are other defects, each naming the
// field, the file and the element.
TEST(FemMeshFiles, OrientationAndDefectsOfTheFile) {
  FemMesh mesh = structured_box(2, Vec3d(0, 0, 0), Vec3d(0.4, 0.2, 0), {4, 2, 1});
  FemMesh clockwise = mesh;
  for (auto& t : clockwise.elements) std::swap(t[1], t[2]);
  const std::string shape = R"({"type": "mesh", "file": ")";
  const std::string cw = test::write_temp("fem_cw.msh", gmsh_text(clockwise));
  const Scene scene = load_scene_text(scene_text(2, shape + cw + R"("})"),
                                      test::write_temp("fem_cw.json", ""));
  EXPECT_NEAR(mesh_figures(*scene.objects[0].fem_mesh).volume, 0.08, 1e-12);

  FemMesh mixed = mesh;
  std::swap(mixed.elements[5][1], mixed.elements[5][2]);
  const std::string mx = test::write_temp("fem_mixed.msh", gmsh_text(mixed));
  EXPECT_NE(scene_error(scene_text(2, shape + mx + R"("})"))
                .find("objects[0].shape.file: '" + mx + "': element 5 is inverted"),
            std::string::npos)
      << scene_error(scene_text(2, shape + mx + R"("})"));

  FemMesh split = mesh;  // a second piece: a triangle of its own
  const int n = int(split.nodes.size());
  for (const Vec3d& x : {Vec3d(1, 1, 0), Vec3d(1.1, 1, 0), Vec3d(1, 1.1, 0)}) split.nodes.push_back(x);
  split.elements.push_back({n, n + 1, n + 2, -1});
  const std::string sp = test::write_temp("fem_split.msh", gmsh_text(split));
  EXPECT_NE(scene_error(scene_text(2, shape + sp + R"("})"))
                .find("element " + std::to_string(split.elements.size() - 1) +
                      " is not connected to element 0"),
            std::string::npos);

  // Dimensions must agree; mesh_size is for netgen's meshes.
  const std::string tets = test::write_temp(
      "fem_tets.msh", gmsh_text(structured_box(3, Vec3d::Zero(), Vec3d::Constant(0.2), {1, 1, 1})));
  EXPECT_NE(scene_error(scene_text(2, shape + tets + R"("})"))
                .find("objects[0].shape.file: '" + tets + "' holds tetrahedra: a 2D scene takes a mesh of triangles"),
            std::string::npos);
  const std::string tris = test::write_temp("fem_tris.msh", gmsh_text(mesh));
  EXPECT_NE(scene_error(scene_text(3, shape + tris + R"("})"))
                .find("' holds triangles only (a 2D mesh): a 3D scene takes tetrahedra"),
            std::string::npos);
  EXPECT_NE(scene_error(scene_text(3, shape + tets + R"("})", R"(, "mesh_size": 0.1)"))
                .find("objects[0].mesh_size: is for shapes that netgen meshes"),
            std::string::npos);
  // A reader's error keeps its line.
  const std::string cut = test::write_temp("fem_cut.msh", gmsh_text(mesh).substr(0, 120));
  EXPECT_NE(scene_error(scene_text(2, shape + cut + R"("})")).find("objects[0].shape.file: " + cut + ": gmsh: "),
            std::string::npos)
      << scene_error(scene_text(2, shape + cut + R"("})"));
}

// A volume mesh file in an MPM object (and so in a collider or region) is the solid its elements
// fill: lattice sampling puts the same particles in it as in the box it meshes, in 2D and 3D.
TEST(FemMeshFiles, AnMpmObjectSamplesTheSolidTheElementsFill) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const double z = dim == 3 ? 1 : 0;
    const Vec3d lo(0.11, 0.21, 0.13 * z), hi(0.52, 0.43, 0.37 * z);
    const FemMesh mesh = structured_box(dim, lo, hi, {4, 3, 2});
    const std::string f = test::write_temp("fem_mpm_" + std::to_string(dim) + "d.vtu", vtu_bytes(mesh));
    const std::string box = R"({"type": "box", "min": [0.11, 0.21)" + (dim == 3 ? std::string(", 0.13") : "") +
                            R"(], "max": [0.52, 0.43)" + (dim == 3 ? std::string(", 0.37") : "") + "]}";
    const std::string lattice = R"(, "sampling": "grid")";
    auto from_file = make_simulation(load_scene_text(
        scene_text(dim, R"({"type": "mesh", "file": ")" + f + R"("})", lattice, false),
        test::write_temp("fem_mpm.json", "")));
    auto from_box = make_simulation(load_scene_text(scene_text(dim, box, lattice, false),
                                                    test::write_temp("fem_mpm_box.json", "")));
    EXPECT_GT(from_box->num_particles(), 100u);
    EXPECT_EQ(from_file->num_particles(), from_box->num_particles());
  }
}

}  // namespace
}  // namespace tear
