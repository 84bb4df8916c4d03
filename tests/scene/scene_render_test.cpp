// The optional "render" section: defaults, values, the resolved form and its errors.
#include <gtest/gtest.h>

#include "scene_test_util.h"

namespace tear {
namespace {

using nlohmann::json;

json with_render(const json& render) {
  json doc = test::minimal_scene_2d();
  doc["render"] = render;
  return doc;
}

TEST(SceneRender, DefaultsAreResolved) {
  const Scene s = parse_scene(test::minimal_scene_2d(), "a.json");
  EXPECT_EQ(s.render.color, "damage");
  EXPECT_EQ(s.render.width, 960);
  EXPECT_EQ(s.render.height, 540);
  EXPECT_EQ(s.render.samples, 4);
  EXPECT_FALSE(s.render.surface);
  EXPECT_FALSE(s.render.has_position || s.render.has_target || s.render.has_up);
  EXPECT_EQ(s.render.fov_deg, 40);
  EXPECT_EQ(s.resolved["render"], json::parse(R"({
    "camera": {"position": null, "target": null, "up": null, "fov_deg": 40.0},
    "color": "damage", "width": 960, "height": 540, "samples": 4, "surface": false})"));
}

TEST(SceneRender, ValuesAreReadAndRoundTrip) {
  // Camera vectors have three entries in a 2D scene too.
  const Scene s = parse_scene(with_render(json::parse(R"({
    "camera": {"position": [0.5, 0.5, 3], "target": [0.5, 0.4, 0], "fov_deg": 30},
    "color": "velocity", "width": 640, "height": 360.0, "samples": 9, "surface": true})")),
                              "a.json");
  EXPECT_EQ(s.render.color, "velocity");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 360);
  EXPECT_EQ(s.render.samples, 9);
  EXPECT_TRUE(s.render.surface);
  EXPECT_TRUE(s.render.has_position);
  EXPECT_TRUE(s.render.has_target);
  EXPECT_FALSE(s.render.has_up);
  EXPECT_EQ(s.render.position, Vec3d(0.5, 0.5, 3));
  EXPECT_EQ(s.render.target, Vec3d(0.5, 0.4, 0));
  EXPECT_EQ(s.render.fov_deg, 30);
  EXPECT_EQ(s.resolved["render"]["camera"]["position"], json::parse("[0.5, 0.5, 3.0]"));
  const Scene again = parse_scene(s.resolved, "resolved.json");
  EXPECT_EQ(again.resolved, s.resolved);
  EXPECT_EQ(again.render.position, s.render.position);
}

TEST(SceneRender, ErrorsNameThePathAndReason) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"colour": "damage"})", "render.colour: unknown key, did you mean \"color\"?"},
      {R"({"color": "rainbow"})",
       "render.color: unknown value \"rainbow\" (expected one of: damage, material, fibers, "
       "velocity, driving_force, damage_laplacian)"},
      {R"({"width": 8})", "render.width: must be in [16, 16384], got 8"},
      {R"({"height": 1.5})", "render.height: must be an integer, got a number"},
      {R"({"samples": 0})", "render.samples: must be in [1, 1024], got 0"},
      {R"({"surface": "yes"})", "render.surface: must be true or false, got a string"},
      {R"({"camera": [1, 2, 3]})", "render.camera: must be an object, got an array"},
      {R"({"camera": {"position": [1, 2]}})",
       "render.camera.position: must be an array of 3 numbers, got 2 entries"},
      {R"({"camera": {"up": [0, 0, 0]}})", "render.camera.up: must be non-zero"},
      {R"({"camera": {"position": [1, 2, 3], "target": [1, 2, 3]}})",
       "render.camera.target: must differ from render.camera.position"},
      {R"({"camera": {"fov_deg": 180}})", "render.camera.fov_deg: must be in (0, 180), got 180"},
      {R"({"camera": {"fov": 30}})", "render.camera.fov: unknown key"},
      {R"("big")", "render: must be an object, got a string"},
  };
  for (const auto& [render, expected] : cases) {
    const std::string error = test::scene_error(with_render(json::parse(render)), "s.json");
    EXPECT_NE(error.find(std::string("s.json: ") + expected), std::string::npos)
        << render << "\n  got: " << error;
  }
}

}  // namespace
}  // namespace tear
