// Cloth, yarn and a solid in one run of the `tear` executable: tear check reports the meshes,
// every frame writes them as PLY meshes beside the particles, and a resumed run writes the same
// bytes as one that never stopped.
#include "cli_fixture.h"

#include "tear/io/mesh_frames.h"
#include "tear/render/color_map.h"
#include "tear/render/image.h"
#include "../render/render_fixture.h"

namespace tear {
namespace {

class CodimCli : public Cli {
 protected:
  json codim_scene() const {
    return json::parse(R"({
      "name": "codim_cli", "dim": 3, "seed": 5,
      "grid": {"dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1]},
      "time": {"frame_dt": 0.02, "frames": 6},
      "gravity": [0, -9.8, 0],
      "materials": {
        "cloth": {"model": "surface_qr", "E": 3000, "nu": 0.3, "rho": 100, "friction_angle": 20},
        "jelly": {"model": "neo_hookean", "E": 500, "nu": 0.3, "rho": 50},
        "yarn": {"model": "curve_qr", "E": 4000, "nu": 0.3, "rho": 150}
      },
      "objects": [
        {"kind": "surface", "material": "cloth", "thickness": 0.01,
         "shape": {"type": "sheet", "center": [0.5, 0.45, 0.5], "size": [0.5, 0.5],
                   "resolution": [10, 10], "triangulation": "random"}},
        {"kind": "curves", "material": "yarn", "radius": 0.01,
         "shape": {"type": "rope", "from": [0.3, 0.6, 0.4], "to": [0.7, 0.6, 0.6], "segments": 16}},
        {"material": "jelly", "shape": {"type": "sphere", "center": [0.5, 0.75, 0.5], "radius": 0.1}}
      ],
      "boundaries": [{"type": "separate", "friction": 0.3,
                      "shape": {"type": "half_space", "point": [0, 0.2, 0], "normal": [0, 1, 0]}}],
      "output": {"every": 1, "checkpoint_every": 3}
    })");
  }
};

TEST_F(CodimCli, CheckReportsTheMeshesAndRunWritesThemEveryFrame) {
  const std::string s = write_scene(codim_scene());
  ASSERT_EQ(tear("check " + s), 0) << err_;
  EXPECT_NE(out_.find("surface of 121 vertices and 200 triangles, thickness 0.01"),
            std::string::npos)
      << out_;
  EXPECT_NE(out_.find("curves of 17 vertices and 16 segments, radius 0.01"), std::string::npos)
      << out_;
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q"), 0) << err_;
  for (int f = 0; f <= 6; ++f) {
    char name[64];
    std::snprintf(name, sizeof name, "/frames/%05d.surfaces.ply", f);
    const MeshPart cloth = decode_mesh_part_ply(read_file(path("run") + name));
    EXPECT_EQ(cloth.corners, 3);
    EXPECT_EQ(cloth.vertices.count, 121u);
    EXPECT_EQ(cloth.elements.size(), 200u);
    EXPECT_TRUE(cloth.element_columns.has("contact"));
    EXPECT_TRUE(cloth.element_columns.has("normal_stretch"));
    std::snprintf(name, sizeof name, "/frames/%05d.curves.ply", f);
    const MeshPart yarn = decode_mesh_part_ply(read_file(path("run") + name));
    EXPECT_EQ(yarn.corners, 2);
    EXPECT_EQ(yarn.vertices.count, 17u);
    EXPECT_EQ(yarn.elements.size(), 16u);
    EXPECT_EQ(yarn.elements[3], (std::array<uint32_t, 4>{3, 4, 0, 0}));
  }
  // The cloth fell (gravity) and met the floor or the rope: it moved.
  const MeshPart first = decode_mesh_part_ply(read_file(path("run/frames/00000.surfaces.ply")));
  const MeshPart last = decode_mesh_part_ply(read_file(path("run/frames/00006.surfaces.ply")));
  EXPECT_LT(last.vertices.column("y")[60], first.vertices.column("y")[60] - 0.01);
  // Solids stay in the particles' frame.
  EXPECT_EQ(stats(path("run")).back()["particles"].get<size_t>(),
            stats(path("run")).front()["particles"].get<size_t>());
}

TEST_F(CodimCli, ResumedRunWritesTheSameMeshesAndCheckpoint) {
  const std::string s = write_scene(codim_scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("full") + " -q"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --frames 3"), 0) << err_;
  ASSERT_EQ(tear("run " + s + " -o " + path("part") + " -q --resume"), 0) << err_;
  for (const char* name : {"/frames/00006.ply", "/frames/00006.surfaces.ply",
                           "/frames/00006.curves.ply", "/frames/00004.surfaces.ply",
                           "/checkpoints/latest.bin"})
    EXPECT_EQ(read_file(path("full") + name), read_file(path("part") + name)) << name;
}

TEST_F(CodimCli, DegenerateMeshIsRefusedBeforeAnythingIsWritten) {
  write_file_atomic(path("flat.obj"), "v 0.3 0.5 0.3\nv 0.5 0.5 0.3\nv 0.7 0.5 0.3\nf 1 2 3\n");
  json j = codim_scene();
  j["objects"][0]["shape"] = {{"type", "mesh"}, {"file", "flat.obj"}};
  const std::string s = write_scene(j);
  EXPECT_EQ(tear("check " + s), 1);
  EXPECT_NE(err_.find("objects[0].shape: '" + path("flat.obj") +
                      "': triangle 0 has zero area (vertices 0, 1, 2)"),
            std::string::npos)
      << err_;
  EXPECT_EQ(tear("run " + s + " -o " + path("never") + " -q"), 1);
  EXPECT_FALSE(std::filesystem::exists(path("never")));
}

// tear render draws the cloth and the yarn (their material colours cover the picture where
// they are), in world and rest space; a run that kept no PLY meshes is refused by name.
TEST_F(CodimCli, RenderDrawsTheMeshes) {
  json j = codim_scene();
  j["render"] = json::parse(R"({"width": 160, "height": 96, "samples": 1, "color": "material"})");
  const std::string s = write_scene(j);
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q --frames 2"), 0) << err_;
  ASSERT_EQ(tear("render " + path("run") + " --no-video -q --frames 2"), 0) << err_;
  const Image im = decode_png(read_file(path("run/render/00002.png")));
  // Pixels of a material's hue (shaded, saturated; the background and ground are greys and
  // blue-greys, of low saturation).
  auto count = [&](int material) {
    const Rgb c = material_color(material);
    const uint8_t ref[3] = {uint8_t(c[0] * 255), uint8_t(c[1] * 255), uint8_t(c[2] * 255)};
    int n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        const uint8_t* p = im.at(x, y);
        if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) < 40) continue;
        const double dh = std::abs(test::hue(p) - test::hue(ref));
        n += std::min(dh, 360 - dh) < 12;
      }
    return n;
  };
  EXPECT_GT(count(0), 1000) << "cloth";  // materials in name order: cloth, jelly, yarn
  EXPECT_GT(count(2), 30) << "yarn";
  ASSERT_EQ(tear("render " + path("run") + " --no-video -q --space rest"), 0) << err_;
  EXPECT_TRUE(std::filesystem::exists(path("run/render/00002.png")));

  j["output"]["mesh_formats"] = {"obj"};
  const std::string obj = write_scene(j);
  ASSERT_EQ(tear("run " + obj + " -o " + path("obj") + " -q --frames 1"), 0) << err_;
  EXPECT_EQ(tear("render " + path("obj") + " --no-video -q"), 1);
  EXPECT_NE(err_.find(path("obj/frames/00000.curves.obj") + ": the run wrote this mesh part "
                      "without its PLY file"),
            std::string::npos)
      << err_;
}

// tear convert writes the mesh parts in the mesh formats (VTU with DIR/PART.pvd, OBJ, GEO), and
// tear mesh writes them beside the solids' surface.
TEST_F(CodimCli, ConvertAndMeshWriteTheMeshParts) {
  const std::string s = write_scene(codim_scene());
  ASSERT_EQ(tear("run " + s + " -o " + path("run") + " -q --frames 2"), 0) << err_;
  auto lines_starting = [](const std::string& text, const std::string& head) {
    size_t n = 0;
    for (size_t at = 0; at < text.size();) {
      const size_t end = std::min(text.find('\n', at), text.size());
      n += text.compare(at, head.size(), head) == 0;
      at = end + 1;
    }
    return n;
  };
  ASSERT_EQ(tear("convert " + path("run") + " --to vtu"), 0) << err_;
  EXPECT_NE(out_.find("converted 6 meshes of " + path("run") + " to vtu (0 already vtu)"),
            std::string::npos)
      << out_;
  const std::string vtu = read_file(path("run/frames/00002.surfaces.vtu"));
  EXPECT_NE(vtu.find("NumberOfPoints=\"121\" NumberOfCells=\"200\""), std::string::npos);
  EXPECT_NE(read_file(path("run/curves.pvd")).find("frames/00002.curves.vtu"), std::string::npos);
  EXPECT_NE(read_file(path("run/surfaces.pvd")).find("frames/00001.surfaces.vtu"),
            std::string::npos);
  ASSERT_EQ(tear("convert " + path("run") + " --to obj --frames 1:2"), 0) << err_;
  EXPECT_NE(out_.find("converted 4 meshes"), std::string::npos) << out_;
  EXPECT_EQ(lines_starting(read_file(path("run/frames/00001.curves.obj")), "l "), 16u);
  ASSERT_EQ(tear("convert " + path("run") + " --to obj"), 0) << err_;
  EXPECT_NE(out_.find("converted 2 meshes of " + path("run") + " to obj (4 already obj)"),
            std::string::npos)
      << out_;

  ASSERT_EQ(tear("convert " + path("run") + " --to geo --frames 2"), 0) << err_;
  const std::string geo = read_file(path("run/frames/00002.surfaces.geo"));
  EXPECT_EQ(geo.rfind("PGEOMETRY V5\nNPoints 121 NPrims 200\n", 0), 0u) << geo.substr(0, 200);
  EXPECT_EQ(lines_starting(read_file(path("run/frames/00002.curves.geo")), "2 : "), 16u);

  ASSERT_EQ(tear("mesh " + path("run") + " -q --frames 2"), 0) << err_;
  EXPECT_NE(out_.find("and 2 cloth, yarn and hair meshes"), std::string::npos) << out_;
  EXPECT_EQ(lines_starting(read_file(path("run/meshes/00002.surfaces.obj")), "f "), 200u);
  EXPECT_EQ(lines_starting(read_file(path("run/meshes/00002.curves.obj")), "l "), 16u);
  EXPECT_GT(lines_starting(read_file(path("run/meshes/00002.obj")), "f "), 100u);  // the jelly
}

}  // namespace
}  // namespace tear
