// Codimensional meshes in pictures: yarn and hair as round tubes of their radius, cloth as
// two-sided shaded triangles, against the analytic projection; their colours (by map where the
// vertices have its columns, else by material); colliders under them; same pixels for any
// thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "render_fixture.h"
#include "tear/exec/threads.h"
#include "tear/render/color_map.h"
#include "tear/render/legend.h"
#include "tear/render/render.h"

namespace tear {
namespace {

using Eigen::Vector3d;

// A mesh part of the given vertices and elements, all of material `material`, with vertex
// velocities `v` (zero when empty) and, for segments, the element column radius = `radius`.
MeshPart part_of(const std::vector<Vector3d>& x, const std::vector<std::array<uint32_t, 3>>& el,
                 int corners, int material, double radius = 0,
                 const std::vector<Vector3d>& v = {}) {
  MeshPart part;
  part.name = corners == 2 ? "curves" : "surfaces";
  part.corners = corners;
  part.vertices = test::make_frame(x, std::vector<double>(x.size(), 0), v);
  // Meshes have no damage or fibers columns: keep id, x y z, vx vy vz, material.
  PointTable t;
  t.count = x.size();
  for (const char* name : {"id", "x", "y", "z", "vx", "vy", "vz"})
    t.add(name, ColumnType::Float32, part.vertices.column(name));
  t.add("material", ColumnType::UInt8, std::vector<double>(x.size(), double(material)));
  part.vertices = t;
  for (const std::array<uint32_t, 3>& e : el) part.elements.push_back({e[0], e[1], e[2], 0});
  part.element_columns.count = el.size();
  if (corners == 2 && radius > 0)
    part.element_columns.add("radius", ColumnType::Float32, std::vector<double>(el.size(), radius));
  return part;
}

struct View {
  int W = 320, H = 240;
  double fov = 30;
  Vector3d eye = Vector3d(0, 0, 4);
  RenderLook look = test::look_for(3, 0.01);
  RenderSettings settings() const {
    RenderSettings s;
    s.width = W;
    s.height = H;
    s.samples = 8;
    s.camera_position = eye;
    s.camera_target = Vector3d::Zero();
    s.camera_up = Vector3d::UnitY();
    s.fov_deg = fov;
    s.color = ColorBy::Material;
    return s;
  }
  Image render(const std::vector<MeshPart>& meshes, const RenderSettings& s,
               const std::vector<Shape>& colliders = {}) const {
    const Stage stage = fit_stage(PointTable(), look, s, mesh_points(meshes));
    return Renderer().render(PointTable(), look, stage, s, "", colliders, meshes);
  }
  // Pixels per unit length at the target's depth, D away.
  double scale() const { return H / 2.0 / std::tan(0.5 * fov * M_PI / 180) / eye.norm(); }
};

// Saturated pixels of material 1's hue (background, ground and shadows are greys and blues).
bool of_hue(const uint8_t* p, int material) {
  const Rgb c = material_color(material);
  const uint8_t ref[3] = {uint8_t(c[0] * 255), uint8_t(c[1] * 255), uint8_t(c[2] * 255)};
  const int mx = std::max({p[0], p[1], p[2]}), mn = std::min({p[0], p[1], p[2]});
  if (mx - mn < 25) return false;
  double dh = std::abs(test::hue(p) - test::hue(ref));
  return std::min(dh, 360 - dh) < 12;
}

// A straight segment of radius R across the view: the tube's picture is 2 R wide (times the
// pixel scale) and as long as the segment plus its round caps; --radius widens every tube.
TEST(MeshPicture, TubeHasTheWidthOfItsRadius) {
  const View view;
  const double R = 0.04, L = 1.6;
  const MeshPart rope = part_of({Vector3d(-L / 2, 0, 0), Vector3d(0, 0, 0), Vector3d(L / 2, 0, 0)},
                                {{0, 1, 0}, {1, 2, 0}}, 2, 1, R);
  RenderSettings s = view.settings();
  auto width_at = [&](const Image& im, int x) {
    int n = 0;
    for (int y = 0; y < view.H; ++y) n += of_hue(im.at(x, y), 1);
    return n;
  };
  auto length_at = [&](const Image& im, int y) {
    int n = 0;
    const Rect legend = legend_rect(Legend{}, view.W, view.H);
    for (int x = 0; x < view.W; ++x)
      if (!(x >= legend.x && y >= legend.y && y < legend.y + legend.h))
        n += of_hue(im.at(x, y), 1);
    return n;
  };
  const Image im = view.render({rope}, s);
  const double k = view.scale();
  EXPECT_NEAR(width_at(im, view.W / 2), 2 * R * k, 1.5) << "scale " << k << " px per unit";
  EXPECT_NEAR(width_at(im, view.W / 2 + 40), 2 * R * k, 1.5);
  EXPECT_NEAR(length_at(im, view.H / 2), (L + 2 * R) * k, 3);
  // The centre is material 1's colour, lit.
  EXPECT_TRUE(of_hue(im.at(view.W / 2, view.H / 2), 1));
  s.radius = 2 * R;
  EXPECT_NEAR(width_at(view.render({rope}, s), view.W / 2), 4 * R * k, 1.5);
}

// A square sheet facing the camera covers its projected square; seen from behind it is as
// bright (two-sided), and both sides take the material's hue.
TEST(MeshPicture, SheetCoversItsSquareAndIsLitOnBothSides) {
  View view;
  const double a = 0.5;
  const MeshPart sheet =
      part_of({Vector3d(-a, -a, 0), Vector3d(a, -a, 0), Vector3d(a, a, 0), Vector3d(-a, a, 0)},
              {{0, 1, 2}, {0, 2, 3}}, 3, 2);
  size_t covered[2];
  double brightness[2];
  for (int side = 0; side < 2; ++side) {
    view.eye = Vector3d(0, 0, side == 0 ? 4 : -4);
    const Image im = view.render({sheet}, view.settings());
    covered[side] = 0;
    for (int y = 0; y < view.H; ++y)
      for (int x = 0; x < view.W; ++x) covered[side] += of_hue(im.at(x, y), 2);
    const uint8_t* c = im.at(view.W / 2, view.H / 2);
    EXPECT_TRUE(of_hue(c, 2)) << "side " << side;
    brightness[side] = c[0] + c[1] + c[2];
  }
  const double side_px = 2 * a * view.scale();
  EXPECT_NEAR(double(covered[0]), side_px * side_px, 0.04 * side_px * side_px);
  EXPECT_EQ(covered[0], covered[1]);
  EXPECT_GT(brightness[1], 0.6 * brightness[0]);
  EXPECT_GT(brightness[0], 0.6 * brightness[1]);
}

// Vertices with velocities take the velocity map; with the damage map (meshes have no damage)
// they take their material's colour.
TEST(MeshPicture, ColourByMapWhereTheColumnsAreElseByMaterial) {
  const View view;
  const double a = 0.5;
  const std::vector<Vector3d> x = {Vector3d(-a, -a, 0), Vector3d(a, -a, 0), Vector3d(a, a, 0),
                                   Vector3d(-a, a, 0)};
  const MeshPart sheet = part_of(x, {{0, 1, 2}, {0, 2, 3}}, 3, 1, 0,
                                 std::vector<Vector3d>(4, Vector3d(1, 0, 0)));
  RenderSettings s = view.settings();
  s.color = ColorBy::Damage;
  const Image by_material = view.render({sheet}, s);
  EXPECT_TRUE(of_hue(by_material.at(view.W / 2, view.H / 2), 1));
  s.color = ColorBy::Velocity;
  s.range_max = 1;  // every vertex at the top of the map: viridis' yellow
  const Image by_speed = view.render({sheet}, s);
  const uint8_t* p = by_speed.at(view.W / 2, view.H / 2);
  EXPECT_FALSE(of_hue(p, 1));
  EXPECT_GT(int(p[0]), int(p[2]) + 40) << "yellow: more red than blue";
}

// A sphere collider whose top pokes a hundredth through a sheet lying on it (as a round
// collider does between the vertices that touch it) is drawn under the sheet where it is less
// than mesh_gap in front of it, and over it with no gap.
TEST(MeshPicture, ColliderJustInFrontOfAMeshStaysUnderIt) {
  View view;
  view.eye = Vector3d(0, 4, 0.001);
  const double a = 0.5;
  const MeshPart sheet = part_of({Vector3d(-a, 0, -a), Vector3d(a, 0, -a), Vector3d(a, 0, a),
                                  Vector3d(-a, 0, a)},
                                 {{0, 1, 2}, {0, 2, 3}}, 3, 1);
  Shape ball;
  ball.type = Shape::Type::Sphere;
  ball.center = Vector3d(0, -0.29, 0);
  ball.radius = 0.3;
  RenderSettings s = view.settings();
  s.camera_up = Vector3d::UnitZ();
  view.look.mesh_gap = 0.02;
  const Image gap = view.render({sheet}, s, {ball});
  const Image bare = view.render({sheet}, s);
  view.look.mesh_gap = 0;
  const Image none = view.render({sheet}, s, {ball});
  const int cx = view.W / 2, cy = view.H / 2;
  EXPECT_EQ(std::memcmp(gap.at(cx, cy), bare.at(cx, cy), 3), 0);
  EXPECT_NE(std::memcmp(none.at(cx, cy), bare.at(cx, cy), 3), 0);
}

TEST(MeshPicture, SamePixelsForAnyThreadCount) {
  const View view;
  std::vector<Vector3d> x;
  std::vector<std::array<uint32_t, 3>> tri, seg;
  const int n = 12;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      x.emplace_back(-0.5 + double(i) / n, -0.3 + 0.1 * std::sin(3.0 * i / n), -0.5 + double(j) / n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t v = uint32_t(j * (n + 1) + i);
      tri.push_back({v, v + 1, v + uint32_t(n) + 2});
      tri.push_back({v, v + uint32_t(n) + 2, v + uint32_t(n) + 1});
    }
  std::vector<Vector3d> h;
  for (int k = 0; k <= 20; ++k) h.emplace_back(0.3 * std::cos(0.3 * k), 0.05 * k, 0.3 * std::sin(0.3 * k));
  for (uint32_t k = 0; k < 20; ++k) seg.push_back({k, k + 1, 0});
  const std::vector<MeshPart> meshes = {part_of(x, tri, 3, 0), part_of(h, seg, 2, 1, 0.01)};
  RenderSettings s = view.settings();
  s.camera_position = Vector3d(1.5, 1.2, 2.5);
  s.samples = 3;
  std::string one, two;
  {
    const ThreadLimit limit(1);
    one = encode_png(view.render(meshes, s));
  }
  {
    const ThreadLimit limit(2);
    two = encode_png(view.render(meshes, s));
  }
  EXPECT_EQ(one, two);
}

}  // namespace
}  // namespace tear
