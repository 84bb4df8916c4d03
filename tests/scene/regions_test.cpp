// Multi-material bodies: objects[].regions give the particles inside them another material
// (and fibers), first region first; the body is sampled once, so the particles are those of
// the plain object, none doubled at region borders.
#include "tear/scene/sampling.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace tear {
namespace {

using json = nlohmann::json;

// An orange slice in 2D: a 60-degree sector of radius 0.4 with its outer 0.05 as "peel".
json orange(const std::string& sampling) {
  return json::parse(R"({
    "dim": 2, "seed": 4,
    "grid": { "dx": 0.01, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.01, "frames": 1 },
    "materials": { "pulp": { "model": "neo_hookean", "E": 1000, "nu": 0.3, "rho": 1 },
                   "peel": { "model": "neo_hookean", "E": 5000, "nu": 0.3, "rho": 3 },
                   "pith": { "model": "neo_hookean", "E": 2000, "nu": 0.3, "rho": 2 } },
    "objects": [ { "shape": { "type": "wedge", "center": [0.5, 0.1], "direction": [0, 1],
                              "radius": 0.4, "angle_deg": 60 },
                   "material": "pulp", "sampling": ")" + sampling + R"(", "ppc": 4,
                   "fibers": { "type": "radial" },
                   "regions": [
                     { "shape": { "type": "wedge", "center": [0.5, 0.1], "direction": [0, 1],
                                  "radius": 0.5, "inner_radius": 0.35, "angle_deg": 60 },
                       "material": "peel", "fibers": { "type": "circumferential" } },
                     { "shape": { "type": "half_space", "point": [0, 0.2], "normal": [0, 1] },
                       "material": "pith" } ] } ]
  })");
}

TEST(Regions, EachParticleTakesTheFirstRegionThatHoldsItAndNoneIsDoubled) {
  for (const std::string sampling : {"random", "grid"}) {
    const json doc = orange(sampling);
    const Scene s = parse_scene(doc, "orange.json");
    const Particles<2> p = sample_scene<2>(s);
    json plain = doc;
    plain["objects"][0].erase("regions");
    const Particles<2> q = sample_scene<2>(parse_scene(plain, "plain.json"));
    // The same particles as without regions: the body is sampled once.
    ASSERT_EQ(p.size(), q.size());
    EXPECT_EQ(std::memcmp(p.x.data(), q.x.data(), p.size() * sizeof(Vec<2>)), 0);
    // Materials in name order: peel 0, pith 1, pulp 2.
    size_t count[3] = {0, 0, 0};
    for (size_t i = 0; i < p.size(); ++i) {
      const Vec3d x(p.x[i].x(), p.x[i].y(), 0);
      const double r = (x - Vec3d(0.5, 0.1, 0)).norm();
      const int expected = r >= 0.35 ? 0 : x.y() <= 0.2 ? 1 : 2;
      ASSERT_EQ(p.material[i], expected) << x.transpose();
      ++count[expected];
      const double rho[3] = {3, 2, 1};
      EXPECT_DOUBLE_EQ(p.mass[i], rho[expected] * 1e-4 / 4);
      // The peel's fibers run around the centre; the pith keeps the object's radial ones.
      const Eigen::Vector2d radial = (x - Vec3d(0.5, 0.1, 0)).head<2>().normalized();
      const Eigen::Vector2d a1 = p.fiber[i].col(0).cast<double>();
      if (r > 1e-6) {
        EXPECT_NEAR(std::abs(a1.dot(radial)), expected == 0 ? 0 : 1, 1e-6);
      }
    }
    EXPECT_GT(count[0], 100u);
    EXPECT_GT(count[1], 100u);
    EXPECT_GT(count[2], 100u);
    EXPECT_EQ(s.resolved["objects"][0]["regions"][1]["fibers"]["type"], "radial");
  }
}

TEST(Regions, Errors) {
  json doc = orange("random");
  doc["objects"][0]["regions"][0]["material"] = "zest";
  EXPECT_EQ(test::scene_error(doc),
            "broken.json: objects[0].regions[0].material: unknown material \"zest\" (defined: "
            "peel, pith, pulp)");
  doc = orange("random");
  doc["objects"][0]["regions"][1].erase("shape");
  EXPECT_EQ(test::scene_error(doc), "broken.json: objects[0].regions[1].shape: required");
  doc = orange("random");
  doc["objects"][0]["regions"] = {{"material", "peel"}};
  EXPECT_NE(test::scene_error(doc).find("objects[0].regions: must be an array of {shape, "
                                        "material}, got an object"),
            std::string::npos)
      << test::scene_error(doc);
  doc = orange("random");
  doc["objects"][0]["regions"][0]["ppc"] = 9;
  EXPECT_NE(test::scene_error(doc).find("objects[0].regions[0].ppc: unknown key"), std::string::npos)
      << test::scene_error(doc);
}

}  // namespace
}  // namespace tear
