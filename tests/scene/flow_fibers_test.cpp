// Flow fibers: the potential flow from sources to sinks. A channel held at 1 and 0 on its ends
// gives the exact uniform flow; a point source and sink in a box give unit fibers from the one
// to the other, tangent to the walls, from a harmonic potential; a torus mesh in 3D; errors.
#include "tear/scene/flow_fibers.h"
#include "tear/scene/sampling.h"
#include "scene_test_util.h"
#include "../geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace tear {
namespace {

using json = nlohmann::json;

Shape box2(const Vec3d& lo, const Vec3d& hi) {
  Shape s;
  s.type = Shape::Type::Box, s.dim = 2, s.min = lo, s.max = hi;
  return s;
}

TEST(FlowFibers, ChannelHeldAtItsEndsFlowsUniformly) {
  // Sources along the left end, sinks along the right: phi is linear, the flow exactly +x.
  const double h = 0.02;
  const Shape channel = box2(Vec3d(0.1, 0.3, 0), Vec3d(0.9, 0.5, 0));
  std::vector<Vec3d> sources, sinks;
  for (double y = 0.31; y < 0.5; y += h) sources.emplace_back(0.11, y, 0), sinks.emplace_back(0.89, y, 0);
  const FlowField flow(channel, 2, h, sources, sinks, 0.6 * h);
  for (double x = 0.15; x < 0.86; x += 0.037)
    for (double y = 0.31; y < 0.5; y += 0.031) {
      const Vec3d a = flow.direction(Vec3d(x, y, 0), Vec3d::UnitY());
      EXPECT_NEAR((a - Vec3d::UnitX()).norm(), 0, 1e-6) << x << " " << y;
    }
  // Linear in x between the held columns (cell centres 0.11 and 0.89).
  EXPECT_NEAR(flow.potential(Vec3d(0.5, 0.4, 0)), (0.89 - 0.51) / (0.89 - 0.11), 1e-6);
}

TEST(FlowFibers, PointSourceAndSinkInABox) {
  const double h = 0.01;
  const Shape box = box2(Vec3d(0.2, 0.2, 0), Vec3d(0.8, 0.6, 0));
  const FlowField flow(box, 2, h, {Vec3d(0.25, 0.4, 0)}, {Vec3d(0.75, 0.4, 0)}, 2 * h);
  // Harmonic: at free cells away from the held ones and the walls, the discrete Laplacian of
  // the potential vanishes (to the solver's tolerance).
  for (double x = 0.305; x < 0.7; x += 0.05)
    for (double y = 0.235; y < 0.57; y += 0.05) {
      const Vec3d c(x, y, 0);
      double lap = -4 * flow.potential(c);
      for (const Vec3d& d : {Vec3d(h, 0, 0), Vec3d(-h, 0, 0), Vec3d(0, h, 0), Vec3d(0, -h, 0)})
        lap += flow.potential(c + d);
      EXPECT_NEAR(lap, 0, 1e-8) << x << " " << y;
    }
  int along = 0, total = 0;
  for (double x = 0.205; x < 0.8; x += 0.013)
    for (double y = 0.205; y < 0.6; y += 0.011) {
      const Vec3d a = flow.direction(Vec3d(x, y, 0), Vec3d::Zero());
      ASSERT_NEAR(a.norm(), 1, 1e-12) << x << " " << y;  // the flow reaches everywhere
      ++total;
      along += a.x() > 0;  // from the source (left) to the sink (right)
    }
  // Tangent to the walls: on them, no normal component.
  for (double t = 0.2; t <= 0.8; t += 0.0137) {
    for (const double y : {0.2, 0.6})
      EXPECT_LT(std::abs(flow.direction(Vec3d(t, y, 0), Vec3d::Zero()).y()), 1e-9) << t << " " << y;
    if (t <= 0.6) {
      for (const double x : {0.2, 0.8})
        EXPECT_LT(std::abs(flow.direction(Vec3d(x, t, 0), Vec3d::Zero()).x()), 1e-9) << x << " " << t;
    }
  }
  EXPECT_GT(along, total * 95 / 100);
  // The potential falls from the source to the sink along the middle line.
  double previous = 2;
  for (double x = 0.305; x < 0.7; x += 0.05) {
    const double phi = flow.potential(Vec3d(x, 0.405, 0));
    EXPECT_LT(phi, previous);
    previous = phi;
  }
}

TEST(FlowFibers, AroundATorusMeshFromSourceToSink) {
  // A source and a sink on opposite sides of the ring: the flow goes round both ways,
  // counter-clockwise over y > 0 and clockwise over y < 0, and runs along the tube's surface.
  const double R = 0.3, r = 0.1, h = 0.0125;
  const test::TestMesh m = test::torus_mesh(Vec3d(0.5, 0.5, 0.5), R, r, 64, 32);
  Shape torus;
  torus.type = Shape::Type::Mesh;
  torus.mesh = std::make_shared<const MeshSolid>(m.vertices, m.triangles);
  const FlowField flow(torus, 3, h, {Vec3d(0.5 + R, 0.5, 0.5)}, {Vec3d(0.5 - R, 0.5, 0.5)}, 2 * h);
  int checked = 0, round = 0;
  double normal_sum = 0;
  int near_surface = 0;
  for (double t = 0.1; t < 6.2; t += 0.07)
    for (double v = 0; v < 6.28; v += 0.5)
      for (double rho : {0.02, 0.05, 0.085}) {
        const Vec3d radial(std::cos(t), std::sin(t), 0), around(-std::sin(t), std::cos(t), 0);
        const Vec3d tube = std::cos(v) * radial + std::sin(v) * Vec3d::UnitZ();
        const Vec3d p = Vec3d(0.5, 0.5, 0.5) + R * radial + rho * tube;
        if (std::abs(std::sin(t)) < 0.3) continue;  // near the source and the sink
        const Vec3d a = flow.direction(p, Vec3d::Zero());
        ASSERT_NEAR(a.norm(), 1, 1e-12);
        ++checked;
        round += (std::sin(t) > 0 ? 1 : -1) * a.dot(around) > 0.9;
        if (rho > 0.08) normal_sum += std::abs(a.dot(tube)), ++near_surface;
      }
  EXPECT_GT(round, checked * 95 / 100) << round << " of " << checked;
  EXPECT_LT(normal_sum / near_surface, 0.1);  // along the surface, a little way inside it
}

TEST(FlowFibers, SceneFibersFollowTheFlowAndRefuseBadPoints) {
  json doc = test::minimal_scene_2d();
  doc["grid"]["dx"] = 0.01;
  doc["objects"][0]["fibers"] = {{"type", "flow"}, {"sources", {{0.25, 0.4}}}, {"sinks", {{0.55, 0.4}}},
                                 {"a2", {0, 1}}};
  const Scene s = parse_scene(doc, "flow.json");
  EXPECT_EQ(s.resolved["objects"][0]["fibers"]["radius"], 0.0);
  const Particles<2> p = sample_scene<2>(s);
  const FlowField flow(s.objects[0].shape, 2, 0.01, {Vec3d(0.25, 0.4, 0)}, {Vec3d(0.55, 0.4, 0)},
                       0.02);
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3d x(p.x[i].x(), p.x[i].y(), 0);
    const Vec3d a = flow.direction(x, Vec3d::UnitX());
    EXPECT_NEAR((p.fiber[i].col(0) - a.head<2>()).norm(), 0, 1e-12);
    EXPECT_NEAR(p.fiber[i].determinant(), 1, 1e-12);
  }
  // A source off the body, no sinks, flow fibers on a region.
  doc["objects"][0]["fibers"]["sources"] = {{0.9, 0.9}};
  try {
    sample_scene<2>(parse_scene(doc, "flow.json"));
    ADD_FAILURE() << "sampled";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "flow.json: objects[0].fibers: source 0 (0.9, 0.9) is not within 0.020000 of the "
              "shape's inside");
  }
  doc["objects"][0]["fibers"].erase("sinks");
  EXPECT_EQ(test::scene_error(doc),
            "broken.json: objects[0].fibers.sinks: required (an array of points)");
  doc = test::minimal_scene_2d();
  doc["objects"][0]["regions"] = {{{"shape", {{"type", "box"}, {"min", {0, 0}}, {"max", {1, 1}}}},
                                   {"material", "jelly"},
                                   {"fibers", {{"type", "flow"}, {"sources", {{0.3, 0.3}}},
                                               {"sinks", {{0.5, 0.5}}}}}}};
  EXPECT_EQ(test::scene_error(doc),
            "broken.json: objects[0].regions[0].fibers.type: \"flow\" is for whole objects (give "
            "it to the object; regions inherit it)");
}

}  // namespace
}  // namespace tear
