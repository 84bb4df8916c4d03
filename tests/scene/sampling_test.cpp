// Sampling objects into particles, and fiber frames.
#include "tear/scene/sampling.h"

#include "scene_test_util.h"

#include <cmath>
#include <cstring>

namespace tear {
namespace {

using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

Scene disk_scene(int seed, int ppc, const std::string& sampling = "random") {
  json doc = test::minimal_scene_2d();
  doc["seed"] = seed;
  doc["grid"]["dx"] = 0.01;
  doc["objects"][0] = {{"shape", {{"type", "sphere"}, {"center", {0.5, 0.5}}, {"radius", 0.3}}},
                       {"material", "jelly"}, {"ppc", ppc}, {"sampling", sampling},
                       {"velocity", {1, 0}}, {"angular_velocity", 2}};
  return parse_scene(doc, "disk.json");
}

template <int Dim>
bool same_bits(const Particles<Dim>& a, const Particles<Dim>& b) {
  return a.size() == b.size() &&
         std::memcmp(a.x.data(), b.x.data(), a.size() * sizeof(Vec<Dim>)) == 0 &&
         std::memcmp(a.fiber.data(), b.fiber.data(), a.size() * sizeof(Mat<Dim>)) == 0;
}

template <int Dim>
void expect_proper_frame(const Mat<Dim>& D, double tol = 1e-6) {
  EXPECT_NEAR((D.transpose() * D - Mat<Dim>::Identity()).norm(), 0, tol);
  EXPECT_NEAR(D.determinant(), 1, tol);
}

TEST(Sampling, DiskCountMassVelocityAndInside) {
  for (int ppc : {4, 5}) {  // stratified (2 x 2) and plain uniform
    Scene s = disk_scene(1, ppc);
    Particles<2> p = sample_scene<2>(s);
    double expected = kPi * 0.09 / (0.01 * 0.01) * ppc;
    EXPECT_NEAR(p.size() / expected, 1, 0.02) << "ppc " << ppc;
    const Shape& shape = s.objects[0].shape;
    for (size_t i = 0; i < p.size(); ++i) {
      Vec3d x(p.x[i].x(), p.x[i].y(), 0);
      ASSERT_LE(shape.sdf(x), 0);
      EXPECT_EQ(p.id[i], i);
      EXPECT_NEAR(p.mass[i], 2 * 1e-4 / ppc, 1e-15);
      EXPECT_NEAR(p.vol0[i], 1e-4 / ppc, 1e-15);
      Vec<2> v_expected(1 - 2 * (x.y() - 0.5), 2 * (x.x() - 0.5));
      EXPECT_NEAR((p.v[i] - v_expected).norm(), 0, 1e-12);
      EXPECT_EQ(p.F[i], Mat<2>::Identity());
      EXPECT_EQ(p.damage[i], 0);
    }
  }
}

TEST(Sampling, SphereCount3D) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.04}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {{"shape", {{"type", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.3}}},
                       {"material", "jelly"}};
  Scene s = parse_scene(doc, "ball.json");
  Particles<3> p = sample_scene<3>(s);
  double expected = 4.0 / 3 * kPi * 0.027 / std::pow(0.04, 3) * 8;
  EXPECT_NEAR(p.size() / expected, 1, 0.02);
  for (size_t i = 0; i < p.size(); ++i)
    ASSERT_LE(s.objects[0].shape.sdf(p.x[i].cast<double>()), 0);
}

TEST(Sampling, DeterministicFromSeed) {
  Particles<2> a = sample_scene<2>(disk_scene(3, 4));
  Particles<2> b = sample_scene<2>(disk_scene(3, 4));
  Particles<2> c = sample_scene<2>(disk_scene(4, 4));
  EXPECT_TRUE(same_bits(a, b));
  EXPECT_FALSE(same_bits(a, c));
  size_t n = std::min(a.size(), c.size()), differ = 0;
  for (size_t i = 0; i < n; ++i) differ += a.x[i] != c.x[i];
  EXPECT_GT(differ, n / 2);
}

TEST(Sampling, ObjectsDoNotDisturbEachOther) {
  json doc = test::minimal_scene_2d();
  Particles<2> one = sample_scene<2>(parse_scene(doc, "a.json"));
  doc["objects"].push_back(
      json{{"shape", {{"type", "sphere"}, {"center", {0.8, 0.8}}, {"radius", 0.1}}},
           {"material", "jelly"}});
  Particles<2> two = sample_scene<2>(parse_scene(doc, "a.json"));
  ASSERT_GT(two.size(), one.size());
  for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one.x[i], two.x[i]);  // appended after
}

TEST(Sampling, GridSamplingIsRegular) {
  json doc = test::minimal_scene_2d();
  doc["grid"]["dx"] = 0.1;
  doc["objects"][0]["sampling"] = "grid";
  doc["objects"][0]["ppc"] = 4;
  Particles<2> p = sample_scene<2>(parse_scene(doc, "g.json"));
  ASSERT_EQ(p.size(), 64u);  // box [0.2, 0.6]^2: 8 x 8 sub-cell centres
  for (size_t i = 0; i < p.size(); ++i)
    for (int d = 0; d < 2; ++d) {
      double k = (p.x[i][d] - 0.025) / 0.05;
      EXPECT_NEAR(k, std::round(k), 1e-9);
      EXPECT_GT(p.x[i][d], 0.2);
      EXPECT_LT(p.x[i][d], 0.6);
    }
}

TEST(Sampling, StaysInsideTheDomain) {
  json doc = test::minimal_scene_2d();
  doc["objects"][0]["shape"] = {{"type", "sphere"}, {"center", {0.0, 0.5}}, {"radius", 0.3}};
  Particles<2> p = sample_scene<2>(parse_scene(doc, "edge.json"));
  EXPECT_GT(p.size(), 0u);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_GE(p.x[i].x(), 0);
  double expected = kPi * 0.09 / 2 / (0.05 * 0.05) * 4;
  EXPECT_NEAR(p.size() / expected, 1, 0.05);
}

TEST(Sampling, RotatedTubeIn2DFillsTwoStrips) {
  // A 2D tube is two strips 0.1 <= |r| <= 0.2 either side of its axis, here turned by 90
  // degrees from y to -x: strips along x, above and below y = 0.5.
  json doc = test::minimal_scene_2d();
  doc["grid"]["dx"] = 0.01;
  doc["objects"][0]["shape"] = {{"type", "tube"}, {"center", {0.0, 0.0}}, {"axis", {0, 1}},
                                {"radius", 0.2}, {"inner_radius", 0.1}, {"height", 0.6},
                                {"transform", {{"rotate", 90}, {"translate", {0.5, 0.5}}}}};
  Scene s = parse_scene(doc, "strips.json");
  Particles<2> p = sample_scene<2>(s);
  EXPECT_NEAR(p.size() / (2 * 0.1 * 0.6 / 1e-4 * 4), 1, 0.02);
  for (size_t i = 0; i < p.size(); ++i) {
    double r = std::abs(p.x[i].y() - 0.5);
    ASSERT_TRUE(r >= 0.1 && r <= 0.2 && std::abs(p.x[i].x() - 0.5) <= 0.3) << p.x[i].transpose();
  }
}

TEST(FiberFrame, ConstantAndGramSchmidt) {
  FiberSpec f;
  f.a1 = Vec3d(1, 1, 0).normalized();
  Mat<2> D2 = fiber_frame_at<2>(f, Vec3d(0.3, 0.1, 0), 0);
  expect_proper_frame<2>(D2);
  EXPECT_NEAR((D2.col(0) - Vec<2>(1, 1).normalized()).norm(), 0, 1e-12);
  f.a2 = Vec3d(0, 1, 1).normalized();
  f.has_a2 = true;
  Mat<3> D3 = fiber_frame_at<3>(f, Vec3d::Zero(), 0);
  expect_proper_frame<3>(D3);
  EXPECT_NEAR((D3.col(0) - f.a1).norm(), 0, 1e-12);
  // a2 stays in span{a1, a2}: the third column is normal to the plane of a1 and a2.
  EXPECT_NEAR(std::abs(D3.col(2).dot(f.a1.cross(f.a2).normalized())), 1, 1e-12);
  EXPECT_GT(D3.col(1).dot(f.a2), 0);
  f.has_a2 = false;
  expect_proper_frame<3>(fiber_frame_at<3>(f, Vec3d::Zero(), 0));
}

TEST(FiberFrame, RadialCircumferentialLongitudinal3D) {
  FiberSpec f;
  f.center = Vec3d(0, 0, 1), f.axis = Vec3d::UnitZ();
  f.type = FiberField::Radial;
  Mat<3> D = fiber_frame_at<3>(f, Vec3d(1, 2, 5), 0);
  expect_proper_frame<3>(D);
  EXPECT_NEAR((D.col(0) - Vec3d(1, 2, 0).normalized()).norm(), 0, 1e-12);
  EXPECT_NEAR((D.col(1) - Vec3d::UnitZ()).norm(), 0, 1e-12);  // natural a2: the axis
  f.type = FiberField::Circumferential;
  D = fiber_frame_at<3>(f, Vec3d(1, 0, -3), 0);
  expect_proper_frame<3>(D);
  EXPECT_NEAR((D.col(0) - Vec3d::UnitY()).norm(), 0, 1e-12);
  f.type = FiberField::Longitudinal;
  D = fiber_frame_at<3>(f, Vec3d(0, 1, 0), 0);
  expect_proper_frame<3>(D);
  EXPECT_NEAR((D.col(0) - Vec3d::UnitZ()).norm(), 0, 1e-12);
  EXPECT_NEAR((D.col(1) - Vec3d::UnitY()).norm(), 0, 1e-12);
  // On the axis the radial direction is undefined; any proper frame will do.
  for (FiberField t : {FiberField::Radial, FiberField::Circumferential}) {
    f.type = t;
    expect_proper_frame<3>(fiber_frame_at<3>(f, Vec3d(0, 0, 4), 0));
  }
}

TEST(FiberFrame, RadialCircumferential2D) {
  FiberSpec f;
  f.center = Vec3d(1, 1, 0);
  f.type = FiberField::Radial;
  Mat<2> D = fiber_frame_at<2>(f, Vec3d(1, 3, 0), 0);
  expect_proper_frame<2>(D);
  EXPECT_NEAR((D.col(0) - Vec<2>(0, 1)).norm(), 0, 1e-12);
  f.type = FiberField::Circumferential;  // counter-clockwise
  D = fiber_frame_at<2>(f, Vec3d(2, 1, 0), 0);
  EXPECT_NEAR((D.col(0) - Vec<2>(0, 1)).norm(), 0, 1e-12);
  expect_proper_frame<2>(fiber_frame_at<2>(f, Vec3d(1, 1, 0), 0));
  f.type = FiberField::Longitudinal, f.axis = Vec3d(0, -2, 0);
  EXPECT_NEAR((fiber_frame_at<2>(f, Vec3d(5, 1, 0), 0).col(0) - Vec<2>(0, -1)).norm(), 0, 1e-12);
}

TEST(FiberFrame, RandomIsDeterministicAndSpread) {
  FiberSpec f;
  f.type = FiberField::Random;
  Vec3d mean = Vec3d::Zero();
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    Mat<3> D = fiber_frame_at<3>(f, Vec3d::Zero(), uint64_t(k));
    expect_proper_frame<3>(D);
    EXPECT_EQ(D, fiber_frame_at<3>(f, Vec3d::Ones(), uint64_t(k)));
    mean += D.col(0).cast<double>();
  }
  EXPECT_LT((mean / n).norm(), 0.05);
  EXPECT_NE(fiber_frame_at<2>(f, Vec3d::Zero(), 1), fiber_frame_at<2>(f, Vec3d::Zero(), 2));
}

TEST(FiberFrame, SampledTubeHasCircumferentialFibers) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {{"shape", {{"type", "tube"}, {"center", {0.5, 0.5, 0.5}}, {"axis", {0, 0, 1}},
                                  {"radius", 0.3}, {"inner_radius", 0.2}, {"height", 0.4}}},
                       {"material", "jelly"}, {"fibers", {{"type", "circumferential"}}}};
  Scene s = parse_scene(doc, "tube.json");
  Particles<3> p = sample_scene<3>(s);
  double expected = kPi * (0.09 - 0.04) * 0.4 / std::pow(0.05, 3) * 8;
  EXPECT_NEAR(p.size() / expected, 1, 0.03);
  for (size_t i = 0; i < p.size(); ++i) {
    Vec3d r = p.x[i].cast<double>() - Vec3d(0.5, 0.5, 0.5);
    r.z() = 0;
    Vec3d a1 = p.fiber[i].col(0).cast<double>();
    EXPECT_NEAR(a1.dot(r.normalized()), 0, 1e-9);
    EXPECT_NEAR(a1.z(), 0, 1e-9);
    EXPECT_GT(Vec3d::UnitZ().cross(r).dot(a1), 0);  // counter-clockwise about +z
  }
}

}  // namespace
}  // namespace tear
