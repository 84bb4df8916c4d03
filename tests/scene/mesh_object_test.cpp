// Mesh objects ("shape": {"type": "mesh", "file": ...}): files relative to the scene, the
// sampled volume of a non-convex mesh against its exact volume for every sampling, transforms,
// and the errors that name the scene, the key and the mesh file.
#include "tear/geometry/mesh_solid.h"
#include "tear/io/atomic_file.h"
#include "tear/io/mesh_io.h"
#include "tear/scene/sampling.h"
#include "scene_test_util.h"
#include "../geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace tear {
namespace {

using json = nlohmann::json;

std::string folder() {
  const std::string dir = ::testing::TempDir() + "tear_mesh_objects";
  std::filesystem::create_directories(dir + "/meshes");
  return dir;
}

// The torus about (0.5, 0.5, 0.5), R 0.3, r 0.12, in `file` under folder()/meshes/.
double write_torus(const std::string& file) {
  const test::TestMesh torus = test::torus_mesh(Vec3d(0.5, 0.5, 0.5), 0.3, 0.12, 48, 24);
  const TriMesh t = test::to_trimesh(torus);
  const std::string path = folder() + "/meshes/" + file;
  const std::string ext = file.substr(file.size() - 3);
  write_file_atomic(path, ext == "obj" ? encode_obj(t) : ext == "stl" ? encode_stl(t)
                                                                      : encode_mesh_ply(t));
  std::vector<Vec3d> v;
  for (const auto& x : t.vertices) v.push_back(x.cast<double>());
  std::vector<std::array<int, 3>> tris;
  for (const auto& x : t.triangles) tris.push_back({x[0], x[1], x[2]});
  return MeshSolid(v, tris).volume();
}

TEST(MeshObjects, SampledVolumeMatchesTheMeshForEverySamplingAndFormat) {
  for (const std::string file : {"torus.obj", "torus.stl", "torus.ply"}) {
    const double volume = write_torus(file);
    for (const auto& [sampling, ppc] : {std::pair<std::string, int>{"grid", 8}, {"random", 8},
                                        {"random", 5}}) {
      if (file != "torus.obj" && sampling == "grid") continue;  // the readers: one each
      const std::string scene_path =
          test::write_temp_in(folder(), "torus.json", test::mesh_scene("meshes/" + file, sampling, ppc).dump());
      const Scene s = load_scene(scene_path);
      const Particles<3> p = sample_scene<3>(s);
      double sampled = 0;
      for (size_t i = 0; i < p.size(); ++i) sampled += p.vol0[i];
      EXPECT_NEAR(sampled / volume, 1, 0.03) << file << " " << sampling << " ppc " << ppc;
      const Shape& shape = s.objects[0].shape;
      ASSERT_EQ(shape.type, Shape::Type::Mesh);
      for (size_t i = 0; i < p.size(); ++i) {
        const Vec3d x = p.x[i].cast<double>();
        // Near the analytic torus: the mesh's chords stray at most ~2e-3 from it.
        const double d = std::hypot(std::hypot(x.x() - 0.5, x.y() - 0.5) - 0.3, x.z() - 0.5) - 0.12;
        ASSERT_LT(d, 2e-3) << x.transpose();
      }
      // The resolved scene names the file absolutely, so that it reads from anywhere.
      const std::string resolved = s.resolved["objects"][0]["shape"]["file"];
      EXPECT_EQ(resolved, (std::filesystem::path(folder()) / "meshes" / file).string());
    }
  }
}

TEST(MeshObjects, TransformMovesTheSampledBody) {
  const double volume = write_torus("moved.obj");
  json doc = test::mesh_scene("meshes/moved.obj", "grid", 8);
  // x_world = t + R (0.5 x) with R a quarter turn about x: the torus, centred at (0.5, 0.5,
  // 0.5) in the file, is centred at (0.35, 0.5, 0.25) with its axis along y, half the size.
  doc["objects"][0]["shape"]["transform"] = {
      {"translate", {0.1, 0.75, 0}}, {"scale", 0.5}, {"rotate", {{"axis", {1, 0, 0}}, {"angle_deg", 90}}}};
  const Scene s = load_scene(test::write_temp_in(folder(), "moved.json", doc.dump()));
  const Particles<3> p = sample_scene<3>(s);
  double sampled = 0;
  Vec3d centre = Vec3d::Zero();
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3d w = p.x[i].cast<double>();
    sampled += p.vol0[i], centre += w / double(p.size());
    const double d = std::hypot(std::hypot(w.x() - 0.35, w.z() - 0.25) - 0.15, w.y() - 0.5) - 0.06;
    ASSERT_LT(d, 1e-3) << w.transpose();
  }
  EXPECT_NEAR(sampled / (volume / 8), 1, 0.05);
  EXPECT_NEAR((centre - Vec3d(0.35, 0.5, 0.25)).norm(), 0, 2e-3);
}

std::string mesh_error(const std::string& mesh_text, const std::string& file, int dim = 3) {
  write_file_atomic(folder() + "/meshes/" + file, mesh_text);
  json doc = test::mesh_scene("meshes/" + file, "random", 4);
  if (dim == 2) {
    doc["dim"] = 2;
    doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0}}, {"domain_max", {1, 1}}};
  }
  try {
    load_scene(test::write_temp_in(folder(), "broken.json", doc.dump()));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(MeshObjects, ErrorsNameTheSceneTheKeyAndTheMesh) {
  const std::string scene = folder() + "/broken.json", mesh = folder() + "/meshes/";
  const std::string key = scene + ": objects[0].shape.file: ";
  const std::string cube = encode_obj(test::to_trimesh(test::box_mesh(Vec3d::Constant(0.2), Vec3d::Constant(0.6))));
  EXPECT_EQ(mesh_error(cube, "ok.obj"), "");
  // Open: the cube without its last triangle.
  const std::string open = cube.substr(0, cube.rfind("f "));
  EXPECT_EQ(mesh_error(open, "open.obj").rfind(key + "'" + mesh + "open.obj' is not closed: 3 edge(s)", 0), 0u)
      << mesh_error(open, "open.obj");
  EXPECT_EQ(mesh_error("", "empty.obj"), key + "'" + mesh + "empty.obj' has no triangles");
  EXPECT_EQ(mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "index.obj"),
            key + "'" + mesh + "index.obj': bad OBJ: line 4: vertex index 4 out of range (3 vertices so far)");
  EXPECT_EQ(mesh_error("v 0 nan 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "nan.obj")
                .rfind(key + "'" + mesh + "nan.obj' vertex 0 is not finite", 0),
            0u);
  EXPECT_EQ(mesh_error(cube, "cube.off"),
            key + "'" + mesh + "cube.off': unknown mesh format '.off' (expected .obj, .ply or .stl)");
  EXPECT_EQ(mesh_error(cube, "ok.obj", 2).rfind(
                scene + ": objects[0].shape.file: a 2D scene's \"mesh\" is a triangle mesh file", 0),
            0u);
}

TEST(MeshObjects, MissingFileIsNamed) {
  json doc = test::mesh_scene("meshes/none.obj", "random", 4);
  std::filesystem::remove(folder() + "/meshes/none.obj");
  const std::string scene = test::write_temp_in(folder(), "missing.json", doc.dump());
  try {
    load_scene(scene);
    ADD_FAILURE() << "loaded";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), scene + ": objects[0].shape.file: " + folder() +
                                         "/meshes/none.obj: cannot open: No such file or directory");
  }
}

TEST(MeshObjects, OverlappingShellsStopTheSampling) {
  test::TestMesh both = test::box_mesh(Vec3d::Constant(0.2), Vec3d::Constant(0.6));
  const test::TestMesh b = test::box_mesh(Vec3d(0.4, 0.2, 0.2), Vec3d(0.8, 0.6, 0.6));
  for (const Vec3d& v : b.vertices) both.vertices.push_back(v);
  for (const auto& t : b.triangles) both.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  write_file_atomic(folder() + "/meshes/two.obj", encode_obj(test::to_trimesh(both)));
  const Scene s = load_scene(test::write_temp_in(folder(), "two.json",
                                                 test::mesh_scene("meshes/two.obj", "grid", 8).dump()));
  try {
    sample_scene<3>(s);
    ADD_FAILURE() << "sampled";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh '" + folder() + "/meshes/two.obj' winds 2 times"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tear
