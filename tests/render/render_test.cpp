// The renderer: deterministic pictures, a fitted camera that sees every particle, the picture
// of a known scene (coverage and colours against the analytic projection), the legend.
#include "tear/render/render.h"

#include <gtest/gtest.h>
#include "tear/exec/threads.h"

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "render_fixture.h"
#include "tear/render/color_map.h"
#include "tear/render/legend.h"

namespace tear {
namespace {

using Eigen::Vector3d;
using test::hue;
using test::look_for;
using test::make_frame;

// A jittered block of n^3 points in [0, 0.6] x [0, 0.3] x [0, 0.4] with a damage ramp.
PointTable block(int n, int dim = 3) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::vector<Vector3d> x;
  std::vector<double> d;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < (dim == 3 ? n : 1); ++k) {
        const Vector3d u((i + 0.5 + jitter(rng)) / n, (j + 0.5 + jitter(rng)) / n,
                         dim == 3 ? (k + 0.5 + jitter(rng)) / n : 0.0);
        x.push_back(Vector3d(0.6 * u.x(), 0.3 * u.y(), 0.4 * u.z()));
        d.push_back(u.x());
      }
  return make_frame(x, d);
}

TEST(Render, SamePngBytesTwiceAndForAnyThreadCount) {
  const PointTable frame = block(14);
  const RenderLook look = look_for(3, 0.012);
  RenderSettings s;
  s.width = 160;
  s.height = 96;
  s.samples = 3;
  const Stage stage = fit_stage(frame, look, s);
  Renderer renderer;
  std::string one, two, again;
  {
    const ThreadLimit limit(1);
    one = encode_png(renderer.render(frame, look, stage, s, "FRAME 3"));
  }
  {
    const ThreadLimit limit(2);
    two = encode_png(renderer.render(frame, look, stage, s, "FRAME 3"));
    again = encode_png(Renderer().render(frame, look, stage, s, "FRAME 3"));
  }
  EXPECT_EQ(one, two);
  EXPECT_EQ(two, again);
  // And the picture is not trivially constant: another colour map changes it.
  s.color = ColorBy::Material;
  EXPECT_NE(encode_png(renderer.render(frame, look, stage, s, "FRAME 3")), one);
}

// Every particle centre projects inside the picture, for 3D (elevated view), 2D (looking along
// -z) and a falling body that the camera frames together with the floor below it.
TEST(FitStage, CameraSeesEveryParticle) {
  struct Case {
    int dim;
    bool falls;
    int width, height;
  };
  for (const Case& c : {Case{3, false, 960, 540}, Case{2, false, 960, 540}, Case{3, true, 300, 400},
                        Case{3, false, 100, 800}}) {
    PointTable frame = block(12, c.dim);
    // Move it far from the origin and stretch it along y: the fit must follow.
    std::vector<double>& y = frame.columns[2];
    for (double& v : y) v = 5 + 3 * v;
    RenderLook look = look_for(c.dim, 0.01);
    look.falls = c.falls;
    look.floors = {-1.0, 4.0};  // the higher one is the floor under the body
    RenderSettings s;
    s.width = c.width;
    s.height = c.height;
    const Stage stage = fit_stage(frame, look, s);
    EXPECT_DOUBLE_EQ(stage.ground, 4.0);
    if (c.dim == 2) {
      EXPECT_NEAR(stage.camera.position.x(), stage.camera.target.x(), 1e-9);
      EXPECT_NEAR(stage.camera.position.y(), stage.camera.target.y(), 1e-9);
      EXPECT_GT(stage.camera.position.z(), 0);
    } else {
      EXPECT_GT(stage.camera.position.y(), stage.camera.target.y());  // looks down on it
    }
    size_t inside = 0;
    for (size_t i = 0; i < frame.count; ++i) {
      const Vector3d p(frame.column("x")[i], frame.column("y")[i], frame.column("z")[i]);
      double px = -1, py = -1;
      ASSERT_TRUE(stage.camera.project(p, &px, &py));
      inside += px >= 0 && px < c.width && py >= 0 && py < c.height;
    }
    EXPECT_EQ(inside, frame.count) << "dim " << c.dim << " falls " << c.falls;
    // Not absurdly far away either: the body spans a fair part of the width or the height.
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
    for (size_t i = 0; i < frame.count; ++i) {
      double px, py;
      stage.camera.project(
          Vector3d(frame.column("x")[i], frame.column("y")[i], frame.column("z")[i]), &px, &py);
      x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
    }
    EXPECT_GT(std::max((x1 - x0) / c.width, (y1 - y0) / c.height), c.falls ? 0.3 : 0.6) << c.dim;
  }
}

// Points the picture must also hold (where colliders pull torn pieces) are inside it too, and
// widen the view only as much as they need.
TEST(FitStage, CameraAlsoSeesTheGivenReach) {
  for (int dim : {2, 3}) {
    const PointTable frame = block(10, dim);
    const RenderLook look = look_for(dim, 0.01);
    RenderSettings s;
    s.width = 320, s.height = 180;
    const std::vector<Vector3d> reach = {Vector3d(0.5, 8.0, 0.5), Vector3d(-6.0, -0.5, 0.5)};
    const Stage alone = fit_stage(frame, look, s), wide = fit_stage(frame, look, s, reach);
    for (const Vector3d& p : reach) {
      double px = -1, py = -1;
      ASSERT_TRUE(wide.camera.project(p, &px, &py));
      EXPECT_TRUE(px >= 0 && px < s.width && py >= 0 && py < s.height) << dim << " " << p.transpose();
      const bool seen_alone = alone.camera.project(p, &px, &py) && px >= 0 && px < s.width &&
                              py >= 0 && py < s.height;
      EXPECT_FALSE(seen_alone) << dim;  // the reach is what made it fit
    }
    for (size_t i = 0; i < frame.count; ++i) {
      double px = -1, py = -1;
      ASSERT_TRUE(wide.camera.project(Vector3d(frame.column("x")[i], frame.column("y")[i],
                                               frame.column("z")[i]), &px, &py));
      EXPECT_TRUE(px >= 0 && px < s.width && py >= 0 && py < s.height);
    }
    EXPECT_EQ(fit_stage(frame, look, s, {}).camera.position, alone.camera.position);
  }
}

TEST(FitStage, GivenCameraIsKept) {
  const PointTable frame = block(5);
  RenderSettings s;
  s.camera_position = Vector3d(1, 2, 3);
  s.camera_target = Vector3d(0.1, 0.2, 0.3);
  s.fov_deg = 25;
  const Stage stage = fit_stage(frame, look_for(3, 0.01), s);
  EXPECT_EQ(stage.camera.position, Vector3d(1, 2, 3));
  EXPECT_EQ(stage.camera.target, Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(stage.camera.fov_deg, 25);
  // Straight down with the default up direction is a degenerate camera: a clear error.
  s.camera_position = Vector3d(0.1, 5, 0.3);
  EXPECT_THROW(fit_stage(frame, look_for(3, 0.01), s), std::invalid_argument);
}

// One sphere of radius R, fully cracked, seen on the camera axis from distance D: its picture
// is a disk of radius tan(asin(R / D)) / tan(fov / 2) * H / 2 pixels in the damage colour.
TEST(Render, OneSphereCoversItsAnalyticDiskInTheDamageColour) {
  const double R = 0.5, D = 4, fov = 30;
  const int W = 320, H = 240;
  const PointTable frame = make_frame({Vector3d(0, 0, 0)}, {1.0});
  RenderLook look = look_for(3, R);
  RenderSettings s;
  s.width = W;
  s.height = H;
  s.samples = 16;
  s.camera_position = Vector3d(0, 0, D);
  s.camera_target = Vector3d(0, 0, 0);
  s.fov_deg = fov;
  const Stage stage = fit_stage(frame, look, s);
  const Image image = Renderer().render(frame, look, stage, s);
  ASSERT_EQ(image.width, W);
  ASSERT_EQ(image.height, H);
  // Sphere pixels are the saturated red of the damage map's end; background, ground and its
  // shadow are greys and blues.
  auto sphere_pixel = [](const uint8_t* p) { return p[0] > p[1] + 30 && p[0] > p[2] + 15; };
  const Rect legend = legend_rect(Legend{}, W, H);
  size_t covered = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool in_legend =
          x >= legend.x && x < legend.x + legend.w && y >= legend.y && y < legend.y + legend.h;
      if (!in_legend) covered += sphere_pixel(image.at(x, y));
    }
  const double r_px = std::tan(std::asin(R / D)) / std::tan(0.5 * fov * M_PI / 180) * H / 2;
  const double expected = M_PI * r_px * r_px;
  EXPECT_NEAR(double(covered), expected, 0.03 * expected) << "disk radius " << r_px << " px";
  // Centre: the damage colour's hue (shading by white light keeps hue).
  const uint8_t* centre = image.at(W / 2, H / 2);
  const Rgb cracked = damage_color(1);
  const uint8_t ref[3] = {uint8_t(cracked[0] * 255), uint8_t(cracked[1] * 255),
                          uint8_t(cracked[2] * 255)};
  double dh = std::abs(hue(centre) - hue(ref));
  dh = std::min(dh, 360 - dh);
  EXPECT_LT(dh, 8) << int(centre[0]) << " " << int(centre[1]) << " " << int(centre[2]);
  EXPECT_TRUE(sphere_pixel(centre));
  // Just outside the disk, and the top-left corner: background (sky blue-grey, no red).
  for (const uint8_t* p : {image.at(0, 0), image.at(W / 2 + int(r_px) + 4, H / 2 - int(r_px))}) {
    EXPECT_FALSE(sphere_pixel(p));
    EXPECT_GT(int(p[2]), int(p[0]));  // bluish
  }
  // The ground (bottom row, below the sphere) is lit and neither background-blue nor red.
  const uint8_t* ground = image.at(W / 2, H - 1);
  EXPECT_FALSE(sphere_pixel(ground));
}

TEST(Render, LegendIsDrawnAndFollowsTheColourMap) {
  const PointTable frame = block(6);
  const RenderLook look = look_for(3, 0.02);
  RenderSettings s;
  s.width = 480;
  s.height = 270;
  s.samples = 1;
  const Stage stage = fit_stage(frame, look, s);
  Renderer renderer;
  std::vector<Image> images;
  std::vector<Rect> rects;
  for (ColorBy c : {ColorBy::Damage, ColorBy::Velocity, ColorBy::Material, ColorBy::Fibers,
                    ColorBy::DrivingForce, ColorBy::DamageLaplacian}) {
    s.color = c;
    images.push_back(renderer.render(frame, look, stage, s));
    Legend legend;
    legend.color = c;
    legend.material_names = look.material_names;
    rects.push_back(legend_rect(legend, s.width, s.height));
  }
  for (size_t k = 0; k < images.size(); ++k) {
    const Rect& r = rects[k];
    ASSERT_GT(r.w, 20);
    ASSERT_GT(r.h, 10);
    EXPECT_LE(r.x + r.w, s.width);
    EXPECT_GE(r.y, 0);
    EXPECT_GT(r.x, s.width / 2);  // top right
    // Ink: dark text pixels in the panel.
    size_t dark = 0;
    for (int y = r.y; y < r.y + r.h; ++y)
      for (int x = r.x; x < r.x + r.w; ++x) dark += images[k].at(x, y)[0] < 60;
    EXPECT_GT(dark, 30u) << k;
  }
  // The damage and velocity legends differ inside the damage legend's panel.
  size_t differ = 0;
  const Rect& r = rects[0];
  for (int y = r.y; y < r.y + r.h; ++y)
    for (int x = r.x; x < r.x + r.w; ++x)
      differ += std::memcmp(images[0].at(x, y), images[1].at(x, y), 3) != 0;
  EXPECT_GT(differ, size_t(r.w * r.h / 10));
}

TEST(Render, MissingColumnIsAClearError) {
  PointTable frame;
  frame.count = 1;
  frame.add("x", ColumnType::Float32, {0});
  frame.add("y", ColumnType::Float32, {0});
  frame.add("z", ColumnType::Float32, {0});
  RenderSettings s;
  s.width = s.height = 32;
  s.color = ColorBy::Fibers;
  const RenderLook look = look_for(3, 0.1);
  try {
    Renderer().render(frame, look, fit_stage(frame, look, s), s);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--color fibers: the frame has no column 'fx'"),
              std::string::npos)
        << e.what();
  }
  s.color = ColorBy::DamageLaplacian;
  try {
    Renderer().render(frame, look, fit_stage(frame, look, s), s);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "--color damage_laplacian: the frame has no column 'damage_laplacian'"),
              std::string::npos)
        << e.what();
  }
}

// The centre pixel of one large sphere whose driving_force and damage_laplacian are `value`,
// coloured by `c` with the map's range `range`.
std::array<uint8_t, 3> sphere_centre(ColorBy c, double value, double range) {
  const PointTable frame = make_frame({Vector3d::Zero()}, {0.0}, {}, {value});
  const RenderLook look = look_for(3, 0.5);
  RenderSettings s;
  s.width = 320;  // wide enough that the legend (top right) leaves the centre free
  s.height = 240;
  s.samples = 4;
  s.camera_position = Vector3d(0, 0, 2);
  s.camera_target = Vector3d::Zero();
  s.color = c;
  s.range_max = range;
  const Image image = Renderer().render(frame, look, fit_stage(frame, look, s), s);
  const uint8_t* p = image.at(160, 120);
  return {p[0], p[1], p[2]};
}

// Lit by white light, a sphere keeps the hue of its map's colour: the driving force's top is
// YlGnBu's deep blue and its middle a teal; the damage Laplacian's ends are RdBu's red (+) and
// blue (-). Values beyond the range take the end colour.
TEST(Render, DrivingForceAndDamageLaplacianTakeTheirMapsColours) {
  struct Case {
    ColorBy c;
    double value, range;
    Rgb expected;
  };
  for (const Case& k : {Case{ColorBy::DrivingForce, 3, 3, driving_force_color(1)},
                        Case{ColorBy::DrivingForce, 1.5, 3, driving_force_color(0.5)},
                        Case{ColorBy::DamageLaplacian, 40, 40, diverging_color(1)},
                        Case{ColorBy::DamageLaplacian, -40, 40, diverging_color(-1)},
                        Case{ColorBy::DamageLaplacian, -20, 40, diverging_color(-0.5)}}) {
    const std::array<uint8_t, 3> got = sphere_centre(k.c, k.value, k.range);
    const uint8_t ref[3] = {uint8_t(k.expected[0] * 255), uint8_t(k.expected[1] * 255),
                            uint8_t(k.expected[2] * 255)};
    double dh = std::abs(hue(got.data()) - hue(ref));
    dh = std::min(dh, 360 - dh);
    EXPECT_LT(dh, 10) << color_by_name(k.c) << " " << k.value << ": " << int(got[0]) << " "
                      << int(got[1]) << " " << int(got[2]);
  }
  // The known hues themselves: blue, red, blue.
  EXPECT_NEAR(hue(sphere_centre(ColorBy::DrivingForce, 3, 3).data()), 228, 15);
  EXPECT_GT(sphere_centre(ColorBy::DamageLaplacian, 40, 40)[0],
            2 * sphere_centre(ColorBy::DamageLaplacian, 40, 40)[2]);
  EXPECT_GT(sphere_centre(ColorBy::DamageLaplacian, -40, 40)[2],
            2 * sphere_centre(ColorBy::DamageLaplacian, -40, 40)[0]);
  // Clamped beyond the range; the range scales the map.
  EXPECT_EQ(sphere_centre(ColorBy::DamageLaplacian, -400, 40),
            sphere_centre(ColorBy::DamageLaplacian, -40, 40));
  EXPECT_EQ(sphere_centre(ColorBy::DrivingForce, 3, 6),
            sphere_centre(ColorBy::DrivingForce, 1.5, 3));
  EXPECT_NE(sphere_centre(ColorBy::DrivingForce, 3, 6), sphere_centre(ColorBy::DrivingForce, 3, 3));
}

TEST(Render, ColourRangeIsTheLargestSpeedOrThe99thPercentile) {
  std::vector<Vector3d> x(200, Vector3d::Zero()), v(200, Vector3d::Zero());
  std::vector<double> value(200);
  for (int i = 0; i < 200; ++i) value[size_t(i)] = i % 2 ? -double(i) : double(i);
  v[7] = Vector3d(3, 4, 0);
  const PointTable frame = make_frame(x, std::vector<double>(200, 0), v, value);
  // |values| 0..199: the 99th percentile is the 198th smallest of 200 (index 0.99 * 199).
  EXPECT_NEAR(color_range_top(frame, ColorBy::DamageLaplacian), 197, 1e-9);
  EXPECT_NEAR(color_range_top(frame, ColorBy::DrivingForce), 197, 1e-9);
  EXPECT_NEAR(color_range_top(frame, ColorBy::Velocity), 5, 1e-6);
  EXPECT_EQ(color_range_top(frame, ColorBy::Damage), 0);
  EXPECT_TRUE(has_range(ColorBy::DamageLaplacian) && !has_range(ColorBy::Fibers));
  PointTable bare;
  bare.count = 1;
  bare.add("x", ColumnType::Float32, {0});
  EXPECT_EQ(color_range_top(bare, ColorBy::DrivingForce), 0);
}

TEST(Render, ColourMapNamesRoundTrip) {
  for (ColorBy c : {ColorBy::Damage, ColorBy::Material, ColorBy::Fibers, ColorBy::Velocity,
                    ColorBy::DrivingForce, ColorBy::DamageLaplacian})
    EXPECT_EQ(parse_color_by(color_by_name(c)), c);
  EXPECT_THROW(parse_color_by("rainbow"), std::invalid_argument);
}

TEST(Render, ParticleRadiusByMaterialOrOverride) {
  const PointTable frame = block(2);  // materials alternate 0, 1
  RenderLook look = look_for(3, 0.5);
  look.material_radius = {0.25};  // material 1 has none: the default radius
  RenderSettings s;
  const std::vector<float> r = particle_radii(frame, look, s);
  EXPECT_FLOAT_EQ(r[0], 0.25f);
  EXPECT_FLOAT_EQ(r[1], 0.5f);
  s.radius = 0.1;
  EXPECT_FLOAT_EQ(particle_radii(frame, look, s)[0], 0.1f);
  EXPECT_NEAR(max_speed(make_frame({Vector3d::Zero()}, {0}, {Vector3d(3, 4, 0)})), 5, 1e-6);
}

TEST(Render, EmptyFrameGivesBackgroundAndLegend) {
  const PointTable frame = make_frame({}, {});
  const RenderLook look = look_for(3, 0.1);
  RenderSettings s;
  s.width = 200;
  s.height = 150;
  const Image image = Renderer().render(frame, look, fit_stage(frame, look, s), s, "FRAME 0");
  EXPECT_EQ(image.width, 200);
  EXPECT_GT(int(image.at(100, 0)[2]), int(image.at(100, 0)[0]) + 20);  // sky
}

}  // namespace
}  // namespace tear
