// Colliders in pictures (render/collider_layer.h): drawn where their shapes are, translucent
// with an outline, hidden by the body in front of them in 3D and laid over it in 2D; every shape
// type appears, and only where it is.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "../geometry/test_meshes.h"
#include "render_fixture.h"
#include "tear/render/render.h"

namespace tear {
namespace {

using Eigen::Vector3d;

// Corners of the shapes' bounds: what the picture must hold (the driver's collider reach).
std::vector<Vector3d> corners_of(const std::vector<Shape>& shapes) {
  std::vector<Vector3d> out;
  for (const Shape& s : shapes) {
    if (s.type == Shape::Type::HalfSpace) continue;
    Vector3d lo, hi;
    s.bounds(&lo, &hi);
    for (int c = 0; c < 8; ++c)
      out.emplace_back((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                       (c & 4) ? hi.z() : lo.z());
  }
  return out;
}

// Pictures of one frame with and without colliders, from a fixed camera.
struct Pair {
  Stage stage;
  Image with, without;
  int w, h;

  Pair(const PointTable& frame, int dim, const std::vector<Shape>& shapes, const Vector3d& eye,
       int width = 240, int height = 160, double fov = 30) {
    const RenderLook look = test::look_for(dim, 0.1);
    RenderSettings s;
    s.width = w = width;
    s.height = h = height;
    s.samples = 4;
    s.camera_position = eye;
    s.camera_target = Vector3d::Zero();
    s.fov_deg = fov;
    s.color = ColorBy::Damage;
    stage = fit_stage(frame, look, s, corners_of(shapes));
    Renderer r;
    with = r.render(frame, look, stage, s, "", shapes);
    without = r.render(frame, look, stage, s);
  }
  // The pixel where world point p is seen.
  std::pair<int, int> pixel(const Vector3d& p) const {
    double px = -1, py = -1;
    EXPECT_TRUE(stage.camera.project(p, &px, &py));
    return {int(px), int(py)};
  }
  bool same(int x, int y) const { return std::memcmp(with.at(x, y), without.at(x, y), 3) == 0; }
  bool same_at(const Vector3d& p) const {
    const auto [x, y] = pixel(p);
    return same(x, y);
  }
  // The darkest pixel (sum of channels) of `with` within `r` pixels of row y, columns x +- r.
  int darkest_near(int x, int y, int r) const {
    int darkest = 3 * 255;
    for (int i = x - r; i <= x + r; ++i) {
      const uint8_t* c = with.at(i, y);
      darkest = std::min(darkest, int(c[0]) + int(c[1]) + int(c[2]));
    }
    return darkest;
  }
  int brightness(const Image& im, const Vector3d& p) const {
    const auto [x, y] = pixel(p);
    const uint8_t* c = im.at(x, y);
    return int(c[0]) + int(c[1]) + int(c[2]);
  }
  // Pixels that differ, and how many of them lie outside the projection of the box [lo, hi]
  // widened by `margin` pixels.
  std::pair<int, int> changed(const Vector3d& lo, const Vector3d& hi, int margin) const {
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
    for (int c = 0; c < 8; ++c) {
      double px, py;
      stage.camera.project(
          Vector3d((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z()),
          &px, &py);
      x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
    }
    int all = 0, outside = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (same(x, y)) continue;
        ++all;
        outside += x < x0 - margin || x > x1 + margin || y < y0 - margin || y > y1 + margin;
      }
    return {all, outside};
  }
};

Shape box2d(const Vector3d& lo, const Vector3d& hi) {
  Shape s;
  s.type = Shape::Type::Box;
  s.dim = 2;
  s.min = lo;
  s.max = hi;
  return s;
}

Shape sphere(const Vector3d& c, double r) {
  Shape s;
  s.type = Shape::Type::Sphere;
  s.center = c;
  s.radius = r;
  return s;
}

// 2D: the box is filled (darker) and outlined where it is, over the particles it covers (which
// keep their hue), and nothing changes elsewhere.
TEST(ColliderPicture, BoxIn2DIsFilledAndOutlinedWhereItIs) {
  const PointTable frame =
      test::make_frame({Vector3d(-0.6, 0, 0), Vector3d(0.3, 0.1, 0)}, {0.0, 1.0});
  const Vector3d lo(-0.2, -0.3, 0), hi(0.6, 0.3, 0);
  const Pair p(frame, 2, {box2d(lo, hi)}, Vector3d(0, 0, 4));
  // Inside, away from the particles: tinted darker.
  EXPECT_LT(p.brightness(p.with, Vector3d(0.0, -0.15, 0)),
            p.brightness(p.without, Vector3d(0.0, -0.15, 0)) - 30);
  // The right edge: a dark line (within a pixel of the projected edge).
  const auto [ex, ey] = p.pixel(Vector3d(0.6, -0.1, 0));
  EXPECT_LT(p.darkest_near(ex, ey, 1), 3 * 100);
  // Outside: untouched, here and everywhere beyond a pixel or two of the box.
  EXPECT_TRUE(p.same_at(Vector3d(0.85, -0.1, 0)));
  EXPECT_TRUE(p.same_at(Vector3d(-0.6, 0, 0)));  // the particle outside the box
  const auto [all, outside] = p.changed(lo, hi, 2);
  EXPECT_GT(all, 1000);
  EXPECT_EQ(outside, 0);
  // The cracked particle under the box shows through, darker but still red.
  const auto [cx, cy] = p.pixel(Vector3d(0.3, 0.1, 0));
  const uint8_t* under = p.with.at(cx, cy);
  const uint8_t* bare = p.without.at(cx, cy);
  EXPECT_LT(int(under[0]), int(bare[0]));
  double dh = std::abs(test::hue(under) - test::hue(bare));
  EXPECT_LT(std::min(dh, 360 - dh), 20);
  EXPECT_GT(int(under[0]), int(under[2]) + 20);
}

// 3D: a particle in front of a collider hides it (its pixels are those of the picture without
// the collider); around it the collider shows, with a dark silhouette; a collider in front of a
// particle tints it without hiding it.
TEST(ColliderPicture, BodyInFrontHidesTheColliderIn3D) {
  {
    const PointTable frame = test::make_frame({Vector3d(0, 0, 1)}, {1.0});
    const Pair p(frame, 3, {sphere(Vector3d(0, 0, -1), 0.8)}, Vector3d(0, 0, 5), 160, 120);
    const Pair only(test::make_frame({}, {}), 3, {sphere(Vector3d(0, 0, -1), 0.8)},
                    Vector3d(0, 0, 5), 160, 120);
    const auto [cx, cy] = p.pixel(Vector3d(0, 0, 1));
    for (int dx = -3; dx <= 3; ++dx)  // the particle's disk (radius about 17 pixels)
      for (int dy = -3; dy <= 3; ++dy) EXPECT_TRUE(p.same(cx + dx, cy + dy));
    // With no particle the collider is there: the same pixels change.
    EXPECT_FALSE(only.same(cx, cy));
    // Beside the particle, inside the collider's outline: tinted.
    EXPECT_FALSE(p.same_at(Vector3d(0, 0.55, -1)));
    // The silhouette: the collider's disk has angular radius asin(0.8 / 6); within two pixels
    // of it, left of the centre (the legend covers the right), a dark pixel.
    const int r_px =
        int(std::lround(std::tan(std::asin(0.8 / 6)) / std::tan(15 * M_PI / 180) * 60));
    EXPECT_LT(p.darkest_near(cx - r_px, cy, 2), 3 * 100);
    EXPECT_TRUE(p.same(cx - r_px - 5, cy));  // and beyond it, the background as it was
  }
  {
    const PointTable frame = test::make_frame({Vector3d(0, 0, -1)}, {1.0});
    const Pair p(frame, 3, {sphere(Vector3d(0, 0, 1), 0.3)}, Vector3d(0, 0, 5), 160, 120);
    const auto [cx, cy] = p.pixel(Vector3d(0, 0, 1));
    EXPECT_FALSE(p.same(cx, cy));
    const uint8_t* c = p.with.at(cx, cy);
    EXPECT_GT(int(c[0]), int(c[2]) + 15);  // the red particle behind shows through
  }
}

// One shape of every type, in 2D where it has a 2D form and in 3D: it changes the picture, and
// only within its projected bounds (two pixels of outline aside).
TEST(ColliderPicture, EveryShapeTypeAppearsOnlyWhereItIs) {
  const auto mesh = test::box_mesh(Vector3d(-0.3, -0.2, -0.25), Vector3d(0.35, 0.3, 0.2));
  const auto solid = std::make_shared<const MeshSolid>(mesh.vertices, mesh.triangles);
  for (int dim : {2, 3}) {
    std::vector<std::pair<const char*, Shape>> shapes;
    Shape s;
    s.dim = dim;
    s.type = Shape::Type::Box;
    s.min = Vector3d(-0.4, -0.3, -0.2), s.max = Vector3d(0.4, 0.3, 0.2);
    shapes.push_back({"box", s});
    s = sphere(Vector3d(0.05, 0, 0), 0.4);
    s.dim = dim;
    shapes.push_back({"sphere", s});
    s = Shape();
    s.dim = dim;
    s.type = Shape::Type::Cylinder;
    s.axis = Vector3d(0, 1, 0), s.radius = 0.3, s.height = 0.6;
    s.transform.rotate = Eigen::AngleAxisd(0.5, Vector3d::UnitZ()).toRotationMatrix();
    shapes.push_back({"cylinder", s});
    s.type = Shape::Type::Tube;
    s.transform = ShapeTransform();
    s.axis = Vector3d(1, 0, 0), s.radius = 0.4, s.inner_radius = 0.25, s.height = 0.5;
    shapes.push_back({"tube", s});
    s.type = Shape::Type::Cone;
    s.axis = Vector3d(0, 1, 0), s.radius = 0.4, s.radius_top = 0.1, s.inner_radius = 0;
    s.height = 0.6;
    shapes.push_back({"cone", s});
    s.type = Shape::Type::Wedge;
    s.axis = Vector3d(0, 0, 1), s.direction = Vector3d(0, 1, 0), s.angle = 1.5;
    s.radius = 0.45, s.inner_radius = 0.1;
    shapes.push_back({"wedge", s});
    if (dim == 3) {
      s = Shape();
      s.type = Shape::Type::Torus;
      s.axis = Vector3d(0, 0, 1), s.radius = 0.35, s.tube_radius = 0.1;
      shapes.push_back({"torus", s});
      s = Shape();
      s.type = Shape::Type::Mesh;
      s.mesh = solid;
      s.transform.translate = Vector3d(0.05, 0, 0);
      shapes.push_back({"mesh", s});
    }
    // A small body off to the side, so that the picture has particles.
    const PointTable frame = test::make_frame({Vector3d(-0.9, 0.5, 0)}, {0.5});
    const Vector3d eye = dim == 2 ? Vector3d(0, 0, 4) : Vector3d(1.6, 1.2, 2.4);
    for (const auto& [name, shape] : shapes) {
      const Pair p(frame, dim, {shape}, eye, 160, 120, 40);
      Vector3d lo, hi;
      shape.bounds(&lo, &hi);
      const auto [all, outside] = p.changed(lo, hi, 3);
      EXPECT_GT(all, 150) << name << " " << dim << "D";
      EXPECT_EQ(outside, 0) << name << " " << dim << "D";
    }
  }
}

// A half space: in 2D its side of the line is tinted and the line drawn; in 3D a wall is drawn,
// and one facing up at the ground is the ground itself, not drawn again.
TEST(ColliderPicture, HalfSpacesAreDrawnExceptTheGround) {
  Shape wall;
  wall.type = Shape::Type::HalfSpace;
  wall.point = Vector3d(0.2, 0, 0);
  wall.normal = Vector3d(1, 0, 0);  // solid: x <= 0.2
  {
    wall.dim = 2;
    const PointTable frame = test::make_frame({Vector3d(0.6, 0.2, 0)}, {0.0});
    const Pair p(frame, 2, {wall}, Vector3d(0.2, 0, 4));
    EXPECT_LT(p.brightness(p.with, Vector3d(-0.2, 0.1, 0)),
              p.brightness(p.without, Vector3d(-0.2, 0.1, 0)) - 30);
    EXPECT_TRUE(p.same_at(Vector3d(0.4, 0.1, 0)));
    const auto [ex, ey] = p.pixel(Vector3d(0.2, 0.1, 0));
    EXPECT_LT(p.darkest_near(ex, ey, 1), 3 * 100);  // the edge line
  }
  wall.dim = 3;
  const PointTable frame = test::make_frame({Vector3d(0.6, 0.3, 0)}, {0.0});
  const Pair p(frame, 3, {wall}, Vector3d(1.5, 1.0, 2.5));
  EXPECT_FALSE(p.same_at(Vector3d(0.0, 0.3, 0.0)));
  Shape floor;
  floor.type = Shape::Type::HalfSpace;
  floor.normal = Vector3d(0, 1, 0);
  floor.point = Vector3d(0, p.stage.ground, 0);
  const Pair q(frame, 3, {floor}, Vector3d(1.5, 1.0, 2.5));
  ASSERT_EQ(q.stage.ground, p.stage.ground);
  EXPECT_EQ(q.with.rgb, q.without.rgb);
}

}  // namespace
}  // namespace tear
