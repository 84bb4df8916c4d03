// Mesh objects end to end: `tear check` and `tear run` of a 3D scene whose body and collider
// are OBJ/STL meshes; a mesh that winds twice fails with its name and leaves no output.
#include "cli_fixture.h"
#include "tear/io/mesh_io.h"
#include "../geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace tear {
namespace {

namespace fs = std::filesystem;


class MeshObjectCli : public Cli {
 protected:
  // A torus (OBJ) falling onto a sticky box slab given as an STL mesh.
  json mesh_scene() const {
    return json::parse(R"({
      "name": "mesh_cli", "dim": 3, "seed": 2,
      "grid": { "dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1] },
      "time": { "frame_dt": 0.01, "frames": 3 },
      "gravity": [0, 0, -9.8],
      "materials": { "jelly": { "model": "neo_hookean", "E": 2000, "nu": 0.3, "rho": 1 } },
      "objects": [ { "shape": { "type": "mesh", "file": "meshes/torus.obj",
                                "transform": { "translate": [0, 0, -0.05] } },
                     "material": "jelly", "ppc": 8, "velocity": [0, 0, -1] } ],
      "boundaries": [ { "type": "sticky", "shape": { "type": "mesh", "file": "meshes/slab.stl" } } ],
      "output": { "every": 1 }
    })");
  }
  void write_meshes() const {
    fs::create_directories(path("meshes"));
    write_file_atomic(path("meshes/torus.obj"),
                      encode_obj(test::to_trimesh(test::torus_mesh(Vec3d(0.5, 0.5, 0.5), 0.25, 0.1, 32, 16))));
    write_file_atomic(path("meshes/slab.stl"),
                      encode_stl(test::to_trimesh(test::box_mesh(Vec3d(0.1, 0.1, 0.1), Vec3d(0.9, 0.9, 0.3)))));
  }
};

TEST_F(MeshObjectCli, CheckAndRunAMeshBodyOnAMeshCollider) {
  write_meshes();
  const std::string s = write_scene(mesh_scene());
  ASSERT_EQ(tear("check " + s), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " --threads 2 -q"), 0) << err_;
  const std::vector<json> st = stats(path("run"));
  ASSERT_EQ(st.size(), 4u);
  // The torus (exact volume 2 pi^2 R r^2 = 0.0493; the mesh's a little less) sampled at
  // density 1: its mass.
  EXPECT_NEAR(st[0]["mass"].get<double>() / 0.0493, 1, 0.04);
  EXPECT_EQ(st[3]["mass"], st[0]["mass"]);
  // Falling at 1 m/s from 0.05 above the slab's top (closer than a stencil's reach): the
  // sticky mesh holds the nodes inside it, so the body slows down instead of falling faster.
  const double v0 = st[0]["momentum"][2].get<double>(), v3 = st[3]["momentum"][2].get<double>();
  EXPECT_LT(v0, 0);
  EXPECT_GT(v3, v0);
  // The resolved scene names the meshes by absolute path.
  const json resolved = json::parse(read_file(path("run/scene.json")));
  EXPECT_EQ(resolved["objects"][0]["shape"]["file"], path("meshes/torus.obj"));
}

TEST_F(MeshObjectCli, MeshThatWindsTwiceFailsAndWritesNothing) {
  write_meshes();
  test::TestMesh both = test::box_mesh(Vec3d::Constant(0.3), Vec3d::Constant(0.6));
  const test::TestMesh b = test::box_mesh(Vec3d(0.4, 0.3, 0.3), Vec3d(0.7, 0.6, 0.6));
  for (const Vec3d& v : b.vertices) both.vertices.push_back(v);
  for (const auto& t : b.triangles) both.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  write_file_atomic(path("meshes/two.obj"), encode_obj(test::to_trimesh(both)));
  json doc = mesh_scene();
  doc["objects"][0]["shape"] = {{"type", "mesh"}, {"file", "meshes/two.obj"}};
  const std::string s = write_scene(doc, "two.json");
  EXPECT_EQ(tear("run " + s + " -o " + path("never")), 1);
  EXPECT_NE(err_.find("mesh '" + path("meshes/two.obj") + "' winds 2 times around"),
            std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(path("never")));
  // An open mesh is refused when the scene is read, by `tear check` too.
  const std::string obj = read_file(path("meshes/torus.obj"));
  write_file_atomic(path("meshes/open.obj"), obj.substr(0, obj.rfind("f ")));
  doc["objects"][0]["shape"]["file"] = "meshes/open.obj";
  const std::string o = write_scene(doc, "open.json");
  EXPECT_EQ(tear("check " + o), 1);
  EXPECT_NE(err_.find("open.json: objects[0].shape.file: '" + path("meshes/open.obj") +
                      "' is not closed"),
            std::string::npos)
      << err_;
}

}  // namespace
}  // namespace tear
