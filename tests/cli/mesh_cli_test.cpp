// End-to-end tests of `tear mesh`: a mesh per frame in DIR/meshes, formats and frame ranges,
// progress and summary, bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "../surface/mesh_check.h"
#include "cli_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/frames.h"
#include "tear/io/mesh_io.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

class MeshCli : public Cli {
 protected:
  // A finished small run (frames 0..4) in path("run").
  std::string run_folder() {
    const std::string s = write_scene(scene());
    EXPECT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
    return path("run");
  }
};

TEST_F(MeshCli, MeshWritesAClosedMeshPerFrame) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("mesh " + run + " --threads 2"), 0) << err_;
  for (int f = 0; f <= 4; ++f) {
    const std::string obj = run + "/meshes/0000" + std::to_string(f) + ".obj";
    ASSERT_TRUE(fs::exists(obj)) << obj;
    const TriMesh mesh = decode_obj(read_file(obj));
    EXPECT_GT(mesh.triangles.size(), 100u) << obj;
    const MeshCheck c = check_mesh(mesh);  // the disk as a slab, stratified-random samples
    EXPECT_TRUE(c.closed && c.oriented && c.manifold) << obj;
    EXPECT_EQ(c.components, 1) << obj;
  }
  EXPECT_FALSE(fs::exists(run + "/meshes/00000.ply"));  // obj by default
  // dx / sqrt(ppc) of the scene: 0.03125 / 2.
  EXPECT_NE(err_.find("spacing 0.015625 (dx / ppc^(1/dim) in " + run + "/scene.json)"),
            std::string::npos)
      << err_;
  EXPECT_NE(err_.find("mesh 5/5  frame 4  "), std::string::npos) << err_;
  EXPECT_NE(out_.find("meshed 5 frames ("), std::string::npos) << out_;
  EXPECT_NE(out_.find(" to " + run + "/meshes in "), std::string::npos) << out_;
}

TEST_F(MeshCli, FormatsAndFrameRanges) {
  const std::string run = run_folder();
  ASSERT_EQ(tear("mesh " + run + " --frames 1:2 --format obj,ply -q --spacing 0.015625"), 0)
      << err_;
  EXPECT_EQ(err_, "");
  EXPECT_FALSE(fs::exists(run + "/meshes/00000.obj"));
  EXPECT_FALSE(fs::exists(run + "/meshes/00003.obj"));
  const TriMesh obj = decode_obj(read_file(run + "/meshes/00002.obj"));
  const TriMesh ply = decode_mesh_ply(read_file(run + "/meshes/00002.ply"));
  EXPECT_GT(obj.triangles.size(), 100u);
  EXPECT_EQ(obj.triangles, ply.triangles);
  EXPECT_EQ(obj.vertices, ply.vertices);
}

TEST_F(MeshCli, WithoutASceneTheSpacingIsEstimatedFromTheFirstFrame) {
  const std::string run = run_folder();
  // Frames from elsewhere: a lattice (the estimate is exact there), no scene.json.
  PointTable lattice;
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 12; ++j) x.push_back(0.3 + 0.02 * i), y.push_back(0.5 + 0.02 * j);
  lattice.count = x.size();
  lattice.add("x", ColumnType::Float32, x);
  lattice.add("y", ColumnType::Float32, y);
  fs::create_directories(path("points/frames"));
  write_file_atomic(path("points/frames/00003.ply"), encode_points(lattice, "ply"));
  ASSERT_EQ(tear("mesh " + path("points")), 0) << err_;
  EXPECT_NE(err_.find("spacing 0.02 (median nearest-neighbour distance in frame 3)"),
            std::string::npos)
      << err_;
  const TriMesh mesh = decode_obj(read_file(path("points/meshes/00003.obj")));
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.closed && c.oriented && c.manifold);
  float lo = 1, hi = -1;  // a slab one spacing thick
  for (const Eigen::Vector3f& v : mesh.vertices) lo = std::min(lo, v.z()), hi = std::max(hi, v.z());
  EXPECT_NEAR(lo, -0.01, 0.003);
  EXPECT_NEAR(hi, 0.01, 0.003);
  // 240 particles of 0.02^3, less the rounded rim of the slab (about a seventh of so small a one).
  EXPECT_GT(c.volume, 0.8 * 240 * 0.02 * 0.02 * 0.02);
  EXPECT_LT(c.volume, 1.0 * 240 * 0.02 * 0.02 * 0.02);
}

TEST_F(MeshCli, BadInputIsOneLineAndANonZeroExit) {
  EXPECT_EQ(tear("mesh " + path("nowhere")), 1);
  EXPECT_EQ(err_, "tear: " + path("nowhere") + ": no such folder\n");
  const std::string run = run_folder();
  EXPECT_EQ(tear("mesh " + run + " --frames x:y"), 2);
  EXPECT_NE(err_.find("x:y"), std::string::npos) << err_;
  EXPECT_EQ(tear("mesh " + run + " --frames 50:"), 1);
  EXPECT_EQ(err_, "tear: " + run + ": no frames in --frames 50:\n");
  EXPECT_EQ(tear("mesh " + run + " --format stl"), 2);  // a usage error, from the parser
  EXPECT_EQ(tear("mesh " + run + " --voxel 0.9"), 1);
  EXPECT_NE(err_.find("voxel"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(run + "/meshes"));  // nothing written
}

// The OpenVDB half of the mesher is a module loaded by `mesh` (and `info`, surface renders)
// only: without it a run works, `info` says why it is missing, and `mesh` fails with one line
// naming the file it tried, writing nothing.
TEST_F(MeshCli, WithoutTheOpenVdbModuleOnlyMeshingFails) {
  const std::string nowhere = path("no_module");
  fs::create_directories(nowhere);
  ASSERT_EQ(setenv("TEAR_MODULE_DIR", nowhere.c_str(), 1), 0);
  struct Unset {
    ~Unset() { unsetenv("TEAR_MODULE_DIR"); }
  } unset;
  const std::string run = run_folder();
  EXPECT_TRUE(fs::exists(run + "/frames/00004.ply"));
  EXPECT_EQ(tear("info"), 0) << err_;
  EXPECT_NE(out_.find("openvdb     not loaded: the surface mesher needs its OpenVDB module "
                      "libtear_level_set.so"),
            std::string::npos)
      << out_;
  EXPECT_EQ(tear("mesh " + run), 1);
  EXPECT_NE(err_.find(nowhere + "/libtear_level_set.so: no such file"), std::string::npos)
      << err_;
  EXPECT_NE(err_.find(": the surface mesher needs its OpenVDB module"), std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(run + "/meshes/00000.obj"));
  unsetenv("TEAR_MODULE_DIR");
  EXPECT_EQ(tear("info"), 0) << err_;
  EXPECT_NE(out_.find("\nopenvdb     "), std::string::npos) << out_;
  EXPECT_EQ(out_.find("not loaded"), std::string::npos) << out_;
}

}  // namespace
}  // namespace tear
