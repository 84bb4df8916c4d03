// "particles" objects: points read from a PLY file with what else the file has (velocities,
// volumes, material numbers, fibers for "from_file"), a tear frame read back, and the errors.
#include "tear/io/atomic_file.h"
#include "tear/io/ply.h"
#include "tear/scene/sampling.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace tear {
namespace {

using json = nlohmann::json;

std::string folder() {
  const std::string dir = ::testing::TempDir() + "tear_particles_file";
  std::filesystem::create_directories(dir);
  return dir;
}

// Three 2D points with every optional column.
PointTable three_points() {
  PointTable t;
  t.count = 3;
  t.add("x", ColumnType::Float64, {0.2, 0.5, 0.7});
  t.add("y", ColumnType::Float64, {0.3, 0.4, 0.8});
  t.add("vx", ColumnType::Float32, {1, 0, -1});
  t.add("vy", ColumnType::Float32, {0, 2, 0});
  t.add("volume", ColumnType::Float64, {1e-4, 2e-4, 3e-4});
  t.add("material", ColumnType::UInt8, {0, 1, 1});
  t.add("fx", ColumnType::Float32, {3, 0, 1});
  t.add("fy", ColumnType::Float32, {4, 2, 1});
  return t;
}

json scene_with(const std::string& file, const json& fibers = json()) {
  json doc = test::minimal_scene_2d();
  doc["materials"]["bone"] = {{"model", "neo_hookean"}, {"E", 1000}, {"nu", 0.3}, {"rho", 5}};
  doc["objects"][0] = {{"shape", {{"type", "particles"}, {"file", file}}},
                       {"material", "jelly"},
                       {"velocity", {0.5, 0}}};
  if (!fibers.is_null()) doc["objects"][0]["fibers"] = fibers;
  return doc;
}

Particles<2> load(const json& doc, const std::string& name) {
  return sample_scene<2>(load_scene(test::write_temp_in(folder(), name, doc.dump())));
}

TEST(ParticlesFile, PointsTakeEveryColumnTheFileHas) {
  write_file_atomic(folder() + "/three.ply", encode_ply(three_points()));
  const Particles<2> p = load(scene_with("three.ply", {{"type", "from_file"}}), "three.json");
  ASSERT_EQ(p.size(), 3u);
  const double rho[2] = {5, 2};  // bone 0, jelly 1 (name order)
  const Eigen::Vector2d a1[3] = {{0.6, 0.8}, {0, 1}, {std::sqrt(0.5), std::sqrt(0.5)}};
  const PointTable t = three_points();
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(p.id[i], i);
    EXPECT_EQ(p.x[i], Vec<2>(t.column("x")[i], t.column("y")[i]));
    EXPECT_EQ(p.v[i], Vec<2>(t.column("vx")[i], t.column("vy")[i]));  // not the object's
    EXPECT_DOUBLE_EQ(p.vol0[i], t.column("volume")[i]);
    EXPECT_EQ(p.material[i], t.column("material")[i]);
    EXPECT_DOUBLE_EQ(p.mass[i], rho[p.material[i]] * t.column("volume")[i]);
    EXPECT_NEAR((p.fiber[i].col(0) - a1[i]).norm(), 0, 1e-6);
    EXPECT_NEAR(p.fiber[i].determinant(), 1, 1e-12);
  }
}

TEST(ParticlesFile, WithoutOptionalColumnsTheObjectDecides) {
  PointTable t;
  t.count = 2;
  t.add("x", ColumnType::Float32, {0.25, 0.75});
  t.add("y", ColumnType::Float32, {0.5, 0.5});
  write_file_atomic(folder() + "/bare.ply", encode_ply(t));
  json doc = scene_with("bare.ply", {{"type", "constant"}, {"a1", {0, 1}}});
  doc["objects"][0]["ppc"] = 4;
  doc["objects"][0]["regions"] = {
      {{"shape", {{"type", "box"}, {"min", {0.5, 0}}, {"max", {1, 1}}}}, {"material", "bone"}}};
  const Particles<2> p = load(doc, "bare.json");
  ASSERT_EQ(p.size(), 2u);
  const double volume = 0.05 * 0.05 / 4;  // dx^2 / ppc
  EXPECT_EQ(p.v[0], Vec<2>(0.5, 0));
  EXPECT_DOUBLE_EQ(p.vol0[1], volume);
  EXPECT_EQ(p.material[0], 1);  // jelly
  EXPECT_EQ(p.material[1], 0);  // bone, by the region
  EXPECT_DOUBLE_EQ(p.mass[1], 5 * volume);
  EXPECT_NEAR((p.fiber[0].col(0) - Vec<2>(0, 1)).norm(), 0, 1e-12);
}

TEST(ParticlesFile, ATearFrameReadsBack) {
  // A sampled disk written as tear writes frames, read back as a particles object: the same
  // positions, velocities, materials and fibers.
  json disk = test::minimal_scene_2d();
  disk["objects"][0] = {{"shape", {{"type", "sphere"}, {"center", {0.5, 0.5}}, {"radius", 0.2}}},
                        {"material", "jelly"},
                        {"velocity", {0.1, 0.2}},
                        {"fibers", {{"type", "radial"}}}};
  const Particles<2> a = sample_scene<2>(parse_scene(disk, "disk.json"));
  PointTable t;
  t.count = a.size();
  std::vector<double> id, x, y, z, vx, vy, vz, m, fx, fy, fz;
  for (size_t i = 0; i < a.size(); ++i) {
    id.push_back(a.id[i]), x.push_back(float(a.x[i].x())), y.push_back(float(a.x[i].y()));
    z.push_back(0), vx.push_back(float(a.v[i].x())), vy.push_back(float(a.v[i].y()));
    vz.push_back(0), m.push_back(a.material[i]);
    fx.push_back(float(a.fiber[i](0, 0))), fy.push_back(float(a.fiber[i](1, 0))), fz.push_back(0);
  }
  for (const auto& [name, type, col] :
       {std::tuple<std::string, ColumnType, std::vector<double>>{"id", ColumnType::Int32, id},
        {"x", ColumnType::Float32, x}, {"y", ColumnType::Float32, y},
        {"z", ColumnType::Float32, z}, {"vx", ColumnType::Float32, vx},
        {"vy", ColumnType::Float32, vy}, {"vz", ColumnType::Float32, vz},
        {"material", ColumnType::UInt8, m}, {"fx", ColumnType::Float32, fx},
        {"fy", ColumnType::Float32, fy}, {"fz", ColumnType::Float32, fz}})
    t.add(name, type, col);
  write_file_atomic(folder() + "/00000.ply", encode_ply(t));
  json back = disk;
  back["objects"][0]["shape"] = {{"type", "particles"}, {"file", "00000.ply"}};
  back["objects"][0]["fibers"] = {{"type", "from_file"}};
  const Particles<2> b = load(back, "back.json");
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR((b.x[i] - a.x[i]).norm(), 0, 1e-6);
    EXPECT_NEAR((b.v[i] - a.v[i]).norm(), 0, 1e-6);
    EXPECT_NEAR((b.fiber[i] - a.fiber[i]).norm(), 0, 1e-6);
    EXPECT_EQ(b.material[i], a.material[i]);
    EXPECT_DOUBLE_EQ(b.vol0[i], a.vol0[i]);  // dx^dim / ppc, as sampled
  }
}

TEST(ParticlesFile, ErrorsNameTheFileAndThePoint) {
  const std::string dir = folder();
  auto error = [&](const PointTable& t, const json& fibers = json()) {
    write_file_atomic(dir + "/bad.ply", encode_ply(t));
    try {
      load(scene_with("bad.ply", fibers), "bad.json");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string key = dir + "/bad.json: objects[0].shape.file: '" + dir + "/bad.ply': ";
  PointTable t = three_points();
  EXPECT_EQ(error(t), "");
  t.columns[0][1] = 1.5;
  EXPECT_EQ(error(t), key + "point 1 (1.5, 0.4) is outside the grid domain");
  t = three_points();
  t.columns[4][2] = 0;
  EXPECT_EQ(error(t), key + "the volume of point 2 must be > 0, got 0");
  t = three_points();
  t.columns[5][0] = 2;
  EXPECT_EQ(error(t), key + "the material of point 0 is 2, not the number of a material (0 to 1, "
                            "in name order)");
  PointTable no_vy = three_points();
  no_vy.names.erase(no_vy.names.begin() + 3), no_vy.types.erase(no_vy.types.begin() + 3);
  no_vy.columns.erase(no_vy.columns.begin() + 3);
  EXPECT_EQ(error(no_vy), key + "the velocity needs the columns vx, vy (some are missing)");
  PointTable no_fibers = three_points();
  for (int k = 0; k < 2; ++k) {
    no_fibers.names.pop_back(), no_fibers.types.pop_back(), no_fibers.columns.pop_back();
  }
  EXPECT_EQ(error(no_fibers, {{"type", "from_file"}}),
            dir + "/bad.json: objects[0].fibers.type: \"from_file\" needs a \"particles\" shape "
                  "whose file has the columns fx, fy (and f2x, f2y for a second fiber)");
  PointTable empty;
  empty.add("x", ColumnType::Float32, {});
  empty.add("y", ColumnType::Float32, {});
  EXPECT_EQ(error(empty), key + "has no points");
  std::filesystem::remove(dir + "/none.ply");
  try {
    load(scene_with("none.ply"), "none.json");
    ADD_FAILURE() << "loaded";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("objects[0].shape.file: '" + dir + "/none.ply': " + dir +
                                         "/none.ply: cannot open"),
              std::string::npos)
        << e.what();
  }
  // Not as a collider, and from_file needs a particles object.
  json doc = test::minimal_scene_2d();
  doc["boundaries"] = {{{"type", "sticky"}, {"shape", {{"type", "particles"}, {"file", "x.ply"}}}}};
  EXPECT_EQ(test::scene_error(doc), "broken.json: boundaries[0].shape.type: \"particles\" is only "
                                    "for objects (a collider needs a surface)");
  doc = test::minimal_scene_2d();
  doc["objects"][0]["fibers"] = {{"type", "from_file"}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].fibers.type: \"from_file\" needs a "
                                        "\"particles\" shape"),
            std::string::npos);
}

}  // namespace
}  // namespace tear
