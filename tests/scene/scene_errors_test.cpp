// Every broken scene is rejected with "FILE: JSON.PATH: reason".
#include "scene_test_util.h"

namespace tear {
namespace {

using nlohmann::json;

struct BrokenScene {
  const char* patch;     // JSON merge patch (RFC 7386) applied to minimal_scene_2d()
  const char* expected;  // substring of what(), starting at the JSON path
};

const BrokenScene kBroken[] = {
    {R"({"materials": {"jelly": {"nu": 0.7}}})",
     "materials.jelly.nu: must be in (-1, 0.5), got 0.7"},
    {R"({"materials": {"jelly": {"nu": -1}}})", "materials.jelly.nu: must be in (-1, 0.5), got -1"},
    {R"({"materials": {"jelly": {"E": 0}}})", "materials.jelly.E: must be > 0, got 0"},
    {R"({"materials": {"jelly": {"rho": -2}}})", "materials.jelly.rho: must be > 0, got -2"},
    {R"({"materials": {"jelly": {"E": "stiff"}}})", "materials.jelly.E: must be a number, got a string"},
    {R"({"materials": {"jelly": {"model": "rubber"}}})",
     "materials.jelly.model: unknown model \"rubber\""},
    {R"({"materials": {"jelly": {"model": null}}})", "materials.jelly.model: required"},
    {R"({"materials": {"jelly": {"Young": 5}}})", "materials.jelly.Young: unknown key"},
    {R"({"materials": {"jelly": {"fiber_scale": [1, 2, 3]}}})",
     "materials.jelly.fiber_scale: must be an array of 1 number in 2D, got 3 entries"},
    {R"({"materials": {"jelly": {"fiber_scale": [1, 2]}}})",
     "materials.jelly.fiber_scale[1]: must be 0 in 2D (only a1 has a fiber stiffness), got 2"},
    {R"({"materials": {"jelly": {"fiber_scale": [-1]}}})",
     "materials.jelly.fiber_scale[0]: must be >= 0, got -1"},
    {R"({"materials": {"jelly": {"damage": {"sigma_c": 1, "eta": 1, "residual": 1}}}})",
     "materials.jelly.damage.residual: must be in [0, 1), got 1"},
    {R"({"materials": {"jelly": {"damage": {"sigma_c": 1, "eta": 1, "alpha": [-2, 0]}}}})",
     "materials.jelly.damage.alpha: must be in [-1, 0], got -2"},
    {R"({"materials": {"jelly": {"damage": {"eta": 1}}}})", "materials.jelly.damage.sigma_c: required"},
    {R"({"materials": {"jelly": {"damage": {"sigma_c": 1, "eta": 0}}}})",
     "materials.jelly.damage.eta: must be > 0, got 0"},
    {R"({"materials": {"jelly": {"inextensible": true}}})",
     "materials.jelly.inextensible: true: not implemented yet"},
    {R"({"materials": {"jelly": {"plasticity": {"type": "von_mises", "yield_stress": 1}}}})",
     "materials.jelly.plasticity.type: \"von_mises\": not implemented yet"},
    {R"({"materials": []})", "materials: must be an object of NAME: {...}, got an array"},
    {R"({"grid": {"dx": 0}})", "grid.dx: must be > 0, got 0"},
    {R"({"grid": {"dx": null}})", "grid.dx: required"},
    {R"({"grid": {"domain_max": [1, 0]}})", "grid.domain_max: must be > domain_min"},
    {R"({"grid": {"domain_min": [0, 0, 0]}})",
     "grid.domain_min: must be an array of 2 numbers, got 3 entries"},
    {R"({"grid": {"domain_min": [0, "a"]}})", "grid.domain_min[1]: must be a number, got a string"},
    {R"({"grid": {"walls": "bouncy"}})", "grid.walls: unknown value \"bouncy\""},
    {R"({"time": {"cfl": 1.5}})", "time.cfl: must be in (0, 1], got 1.5"},
    {R"({"time": {"cfl": 0}})", "time.cfl: must be in (0, 1], got 0"},
    {R"({"time": {"max_dt": 0}})", "time.max_dt: must be > 0, got 0"},
    {R"({"time": {"frames": -1}})", "time.frames: must be in [0, 1e8], got -1"},
    {R"({"time": {"frames": 2.5}})", "time.frames: must be an integer, got a number (2.5)"},
    {R"({"time": null})", "time: required"},
    {R"({"gravty": [0, -9.8]})", "gravty: unknown key"},
    {R"({"gravity": [0, -9.8, 0]})", "gravity: must be an array of 2 numbers, got 3 entries"},
    {R"({"gravity": "down"})", "gravity: must be an array of 2 numbers, got a string"},
    {R"({"transfer": "mls"})", "transfer: unknown value \"mls\" (expected one of: apic, pic, flip)"},
    {R"({"flip_ratio": 1.5})", "flip_ratio: must be in [0, 1], got 1.5"},
    {R"({"integrator": "implicit"})", "integrator: \"implicit\": not implemented yet"},
    {R"({"dim": 4})", "dim: must be 2 or 3, got 4"},
    {R"({"dim": null})", "dim: required"},
    {R"({"dim": "2"})", "dim: must be an integer, got a string"},
    {R"({"seed": -1})", "seed: must be >= 0, got -1"},
    {R"({"damage": {"solver": "magic"}})", "damage.solver: unknown value \"magic\""},
    {R"({"damage": {"solver": "implicit"}})", "damage.solver: \"implicit\": not implemented yet"},
    {R"({"damage": {"l0": -1}})", "damage.l0: must be > 0, got -1"},
    {R"({"damage": {"transfer": "apic"}})", "damage.transfer: unknown value \"apic\""},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": -1},
                      "material": "jelly"}]})",
     "objects[0].shape.radius: must be > 0, got -1"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "steel"}]})",
     "objects[0].material: unknown material \"steel\" (defined: jelly)"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "ppc": 0}]})",
     "objects[0].ppc: must be in [1, 4096], got 0"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "ppc": 3, "sampling": "grid"}]})",
     "objects[0].ppc: must be a perfect square with \"sampling\": \"grid\", got 3"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "fibers": {"a1": [0, 0]}}]})",
     "objects[0].fibers.a1: must be non-zero"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "fibers": {"type": "spiral"}}]})",
     "objects[0].fibers.type: unknown value \"spiral\""},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "fibers": {"a1": [1, 0], "a2": [2, 0]}}]})",
     "objects[0].fibers.a2: must not be parallel to a1"},
    {R"({"objects": [{"shape": {"type": "sphere", "center": [0.5, 0.5], "radius": 0.1},
                      "material": "jelly", "angular_velocity": [0, 1]}]})",
     "objects[0].angular_velocity: must be a number, got an array"},
    {R"({"objects": [{"shape": {"type": "mesh", "file": "bunny.obj"}, "material": "jelly"}]})",
     "objects[0].shape.type: \"mesh\": not implemented yet"},
    {R"({"objects": [{"shape": {"type": "half_space", "point": [0, 0], "normal": [0, 1]},
                      "material": "jelly"}]})",
     "objects[0].shape.type: \"half_space\" is only allowed for boundaries"},
    {R"({"objects": [{"shape": {"type": "tube", "center": [0.5, 0.5], "axis": [0, 1],
                      "radius": 0.2, "inner_radius": 0.2, "height": 0.5}, "material": "jelly"}]})",
     "objects[0].shape.inner_radius: must be in [0, radius = 0.2), got 0.2"},
    {R"({"objects": [{"shape": {"type": "cylinder", "center": [0.5, 0.5], "axis": [0, 0],
                      "radius": 0.2, "height": 0.5}, "material": "jelly"}]})",
     "objects[0].shape.axis: must be non-zero"},
    {R"({"objects": [{"shape": {"type": "box", "min": [0.5, 0.2], "max": [0.4, 0.6]},
                      "material": "jelly"}]})",
     "objects[0].shape.max: must be > min in every entry"},
    {R"({"objects": [{"shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.6],
                      "transform": {"scale": 0}}, "material": "jelly"}]})",
     "objects[0].shape.transform.scale: must be > 0, got 0"},
    {R"({"objects": [{"shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.6],
                      "radius": 1}, "material": "jelly"}]})",
     "objects[0].shape.radius: unknown key"},
    {R"({"objects": {"shape": 1}})", "objects: must be an array, got an object"},
    {R"({"boundaries": [{"type": "glue", "shape": {"type": "box", "min": [0, 0], "max": [1, 1]}}]})",
     "boundaries[0].type: unknown value \"glue\""},
    {R"({"boundaries": [{"type": "slip", "shape": {"type": "half_space", "point": [0, 0],
                         "normal": [0, 1]}, "friction": -1}]})",
     "boundaries[0].friction: must be >= 0, got -1"},
    {R"({"boundaries": [{"type": "sticky", "shape": {"type": "box", "min": [0, 0], "max": [1, 1]},
                         "start": 2, "end": 1}]})",
     "boundaries[0].end: must be > start (2), got 1"},
    {R"({"boundaries": [{"type": "sticky"}]})", "boundaries[0].shape: required"},
    {R"({"output": {"every": 0}})", "output.every: must be >= 1, got 0"},
    {R"({"output": {"checkpoint_every": -1}})", "output.checkpoint_every: must be >= 0, got -1"},
    {R"({"output": {"formats": ["vtu"]}})", "output.formats[0]: format \"vtu\": not implemented yet"},
    {R"({"output": {"formats": ["ply", "obj"]}})", "output.formats[1]: unknown format \"obj\""},
    {R"({"output": {"formats": ["ply", "ply"]}})", "output.formats[1]: duplicate format \"ply\""},
};

void PrintTo(const BrokenScene& b, std::ostream* os) { *os << b.patch; }

class SceneErrors : public ::testing::TestWithParam<BrokenScene> {};

TEST_P(SceneErrors, NameFilePathAndReason) {
  json doc = test::minimal_scene_2d();
  doc.merge_patch(json::parse(GetParam().patch));
  std::string msg = test::scene_error(doc, "scenes/broken.json");
  ASSERT_FALSE(msg.empty()) << "accepted: " << GetParam().patch;
  EXPECT_EQ(msg.rfind("scenes/broken.json: ", 0), 0u) << msg;
  EXPECT_NE(msg.find(std::string("scenes/broken.json: ") + GetParam().expected), std::string::npos)
      << "message: " << msg << "\nexpected: " << GetParam().expected;
}

INSTANTIATE_TEST_SUITE_P(Table, SceneErrors, ::testing::ValuesIn(kBroken));

// 3D-only rules.
TEST(SceneErrors3D, VectorsNeedThreeEntriesAndRotateIsAxisAngle) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  EXPECT_NE(test::scene_error(doc).find("grid.domain_min: must be an array of 3 numbers"),
            std::string::npos);
  doc["grid"]["domain_min"] = {0, 0, 0};
  doc["grid"]["domain_max"] = {1, 1, 1};
  doc["objects"][0]["shape"] = {{"type", "box"}, {"min", {0.2, 0.2, 0.2}}, {"max", {0.6, 0.6, 0.6}}};
  EXPECT_EQ(test::scene_error(doc), "");
  doc["objects"][0]["shape"]["transform"] = {{"rotate", 30}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].shape.transform.rotate: must be {\"axis\""),
            std::string::npos);
  doc["objects"][0]["shape"]["transform"] = {{"rotate", {{"axis", {0, 0, 0}}, {"angle_deg", 30}}}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].shape.transform.rotate.axis: must be non-zero"),
            std::string::npos);
  doc["objects"][0]["shape"]["transform"] = nullptr;
  doc["materials"]["jelly"]["fiber_scale"] = {1};
  EXPECT_NE(test::scene_error(doc).find("materials.jelly.fiber_scale: must be an array of 2 numbers in 3D"),
            std::string::npos);
  doc["materials"]["jelly"]["fiber_scale"] = 3;  // a scalar sets gamma1 only
  EXPECT_EQ(test::scene_error(doc), "");
}

TEST(SceneErrors, RootMustBeAnObject) {
  EXPECT_EQ(test::scene_error(json::array(), "x.json"), "x.json: (root): must be an object, got an array");
}

TEST(SceneErrors, WhatIsFilePathReason) {
  SceneError e("a.json", "grid.dx", "must be > 0, got 0");
  EXPECT_STREQ(e.what(), "a.json: grid.dx: must be > 0, got 0");
  EXPECT_EQ(e.file(), "a.json");
  EXPECT_EQ(e.path(), "grid.dx");
  EXPECT_EQ(e.reason(), "must be > 0, got 0");
}

}  // namespace
}  // namespace tear
