// cone, torus and wedge in scene files: sampled volume (area in 2D) against the exact one for
// both samplings, the resolved keys, and the errors.
#include "tear/scene/sampling.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace tear {
namespace {

using json = nlohmann::json;
constexpr double kPi = 3.14159265358979323846;

json with_shape(int dim, const json& shape) {
  json doc = test::minimal_scene_2d();
  if (dim == 3) {
    doc["dim"] = 3;
    doc["grid"] = {{"dx", 0.02}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  } else {
    doc["grid"] = {{"dx", 0.005}, {"domain_min", {0, 0}}, {"domain_max", {1, 1}}};
  }
  doc["objects"][0]["shape"] = shape;
  return doc;
}

template <int Dim>
double sampled_volume(const json& doc, const std::string& sampling) {
  json d = doc;
  d["objects"][0]["sampling"] = sampling;
  d["objects"][0]["ppc"] = Dim == 2 ? 4 : 8;
  const Particles<Dim> p = sample_scene<Dim>(parse_scene(d, "round.json"));
  double v = 0;
  for (size_t i = 0; i < p.size(); ++i) v += p.vol0[i];
  return v;
}

TEST(RoundShapeScenes, SampledVolumesMatchTheExactOnes) {
  struct Case {
    int dim;
    json shape;
    double exact;
  };
  const double h = 0.5, rb = 0.3, rt = 0.1;
  const std::vector<Case> cases = {
      {3, {{"type", "cone"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}}, {"height", h},
           {"radius", {rb, rt}}},
       kPi * h / 3 * (rb * rb + rb * rt + rt * rt)},
      {3, {{"type", "cone"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {1, 1, 0}}, {"height", h},
           {"radius", {rb, 0.2}}, {"inner_radius", {0.2, 0.1}}},
       kPi * h / 3 * (rb * rb + rb * 0.2 + 0.04) - kPi * h / 3 * (0.04 + 0.02 + 0.01)},
      {3, {{"type", "torus"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 1, 0}}, {"radius", 0.3},
           {"tube_radius", 0.1}},
       2 * kPi * kPi * 0.3 * 0.01},
      {3, {{"type", "wedge"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}},
           {"direction", {1, 1, 0}}, {"radius", 0.4}, {"inner_radius", 0.3}, {"angle_deg", 60}},
       60.0 / 360 * 4.0 / 3 * kPi * (0.064 - 0.027)},
      {2, {{"type", "cone"}, {"center", {0.5, 0.5}}, {"axis", {0, 1}}, {"height", h},
           {"radius", {rb, rt}}},
       h * (rb + rt)},
      {2, {{"type", "torus"}, {"center", {0.5, 0.5}}, {"axis", {0, 1}}, {"radius", 0.3},
           {"tube_radius", 0.1}},
       2 * kPi * 0.01},
      {2, {{"type", "wedge"}, {"center", {0.3, 0.3}}, {"direction", {1, 1}}, {"radius", 0.6},
           {"angle_deg", 40}},
       0.5 * (40 * kPi / 180) * 0.36}};
  for (const Case& c : cases)
    for (const std::string sampling : {"random", "grid"}) {
      const json doc = with_shape(c.dim, c.shape);
      const double v = c.dim == 2 ? sampled_volume<2>(doc, sampling) : sampled_volume<3>(doc, sampling);
      EXPECT_NEAR(v / c.exact, 1, c.dim == 2 ? 0.01 : 0.03) << c.shape.dump() << " " << sampling;
    }
}

TEST(RoundShapeScenes, ResolvedKeys) {
  const Scene s = parse_scene(with_shape(3, {{"type", "cone"}, {"center", {0.5, 0.5, 0.5}},
                                             {"axis", {0, 0, 2}}, {"height", 0.4}, {"radius", 0.2}}),
                              "cone.json");
  const json& shape = s.resolved["objects"][0]["shape"];
  EXPECT_EQ(shape["radius"], json({0.2, 0.2}));
  EXPECT_EQ(shape["inner_radius"], json({0.0, 0.0}));
  const Scene w = parse_scene(with_shape(2, {{"type", "wedge"}, {"center", {0.5, 0.5}},
                                             {"direction", {0, 1}}, {"radius", 0.2},
                                             {"angle_deg", 45}}),
                              "wedge.json");
  EXPECT_EQ(w.resolved["objects"][0]["shape"]["inner_radius"], 0.0);
  // Radial fibers of a wedge default to its centre and axis (an orange slice's segments).
  EXPECT_EQ(w.resolved["objects"][0]["fibers"]["center"], json({0.5, 0.5}));
}

TEST(RoundShapeScenes, Errors) {
  const std::string p = "broken.json: objects[0].shape.";
  auto error = [](int dim, const json& shape) {
    return test::scene_error(with_shape(dim, shape));
  };
  const json cone = {{"type", "cone"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}},
                     {"height", 0.4}, {"radius", {0.2, 0.1}}};
  EXPECT_EQ(error(3, cone), "");
  json bad = cone;
  bad["radius"] = {0.2, 0};
  EXPECT_EQ(error(3, bad), p + "radius: must be > 0 at both ends, got 0 at the top");
  bad = cone;
  bad["radius"] = {0.2, 0.1, 0.3};
  EXPECT_EQ(error(3, bad), p + "radius: must be a number or [bottom, top], got 3 entries");
  bad = cone;
  bad["inner_radius"] = {0.1, 0.1};
  EXPECT_EQ(error(3, bad),
            p + "inner_radius: must be in [0, radius) at both ends, got 0.1 at the top (radius 0.1)");
  bad = cone;
  bad.erase("height");
  EXPECT_EQ(error(3, bad), p + "height: required");
  const json torus = {{"type", "torus"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}},
                      {"radius", 0.2}, {"tube_radius", 0.2}};
  EXPECT_EQ(error(3, torus),
            p + "tube_radius: must be < radius = 0.2 (a torus with a hole), got 0.2");
  const json wedge = {{"type", "wedge"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}},
                      {"direction", {0, 0, 3}}, {"radius", 0.2}, {"angle_deg", 30}};
  EXPECT_EQ(error(3, wedge), p + "direction: must not be parallel to the axis (it points to the "
                                 "middle of the wedge)");
  bad = wedge;
  bad["direction"] = {1, 0, 0};
  bad["angle_deg"] = 200;
  EXPECT_EQ(error(3, bad), p + "angle_deg: must be in (0, 180] degrees, got 200");
  const json wedge2 = {{"type", "wedge"}, {"center", {0.5, 0.5}}, {"axis", {0, 1}},
                       {"direction", {1, 0}}, {"radius", 0.2}, {"angle_deg", 30}};
  EXPECT_NE(error(2, wedge2).find(p + "axis: unknown key"), std::string::npos) << error(2, wedge2);
}

}  // namespace
}  // namespace tear
