// Sampling objects into particles, and fiber frames.
#include "tear/scene/sampling.h"

#include "tear/exec/threads.h"

#include "scene_test_util.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>

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
  if (a.size() != b.size() || a.enabled("fiber") != b.enabled("fiber") ||
      std::memcmp(a.x.data(), b.x.data(), a.size() * sizeof(Vec<Dim>)) != 0)
    return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a.fiber_of(i), &b.fiber_of(i), sizeof(Mat<Dim>)) != 0) return false;
  return true;
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
  doc["objects"][0] = {
      {"shape", {{"type", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.3}}},
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

// The sampler finds each object's cells row by row in parallel: the particles (positions,
// ids, order) are the same for any thread count, objects come in order, and inside an object
// the cells come x fastest, then y, then z.
TEST(Sampling, SameParticlesAndOrderForAnyThreadCount) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.04}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["materials"]["other"] = doc["materials"]["jelly"];
  doc["objects"] = json::array(
      {{{"shape", {{"type", "sphere"}, {"center", {0.3, 0.4, 0.5}}, {"radius", 0.23}}},
        {"material", "jelly"}, {"ppc", 5}},
       // Partly outside the domain, lattice sampled.
       {{"shape", {{"type", "box"}, {"min", {0.7, -0.2, 0.1}}, {"max", {1.3, 0.33, 0.52}}}},
        {"material", "other"}, {"ppc", 8}, {"sampling", "grid"}},
       {{"shape", {{"type", "sphere"}, {"center", {0.7, 0.7, 0.7}}, {"radius", 0.17}}},
        {"material", "jelly"}, {"ppc", 8}}});
  const Scene scene = parse_scene(doc, "three.json");
  auto sample = [&](int threads) {
    ThreadLimit limit(threads);
    return sample_scene<3>(scene);
  };
  const Particles<3> one = sample(1), two = sample(2), all = sample(0);
  ASSERT_GT(one.size(), 1000u);
  EXPECT_TRUE(same_bits(one, two));
  EXPECT_TRUE(same_bits(one, all));
  EXPECT_EQ(one.id, two.id);
  // Objects in order (told apart by material and by which sphere holds the point), cells in
  // order inside each: (object, z, y, x) of the cell never decreases along the store.
  auto object_of = [&](size_t i) {
    if (one.material[i] == 1) return 1;
    return (one.x[i].cast<double>() - Vec3d(0.3, 0.4, 0.5)).norm() <= 0.23 + 1e-12 ? 0 : 2;
  };
  std::array<long, 4> last{-1, -1, -1, -1};
  for (size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one.id[i], i);
    std::array<long, 4> key{object_of(i), 0, 0, 0};
    for (int d = 0; d < 3; ++d) key[size_t(3 - d)] = long(std::floor(one.x[i][d] / 0.04));
    ASSERT_LE(last, key) << "particle " << i;
    last = key;
  }
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

// spread: each particle's a1 turned by a random angle within the bound, deterministically from
// its key, the angles filling the range (2D: both signs; 3D: all around a1), frames proper.
TEST(FiberFrame, SpreadTurnsFibersWithinItsBound) {
  for (const double spread : {5.0, 30.0}) {
    FiberSpec f;
    f.a1 = Vec3d(1, 2, 2).normalized();
    f.spread = spread;
    const double bound = spread * 3.14159265358979 / 180;
    double largest2 = 0, smallest2 = 0, largest3 = 0;
    Vec3d mean3 = Vec3d::Zero();
    const int n = 4000;
    for (int k = 0; k < n; ++k) {
      const Mat<3> D = fiber_frame_at<3>(f, Vec3d::Zero(), uint64_t(k));
      expect_proper_frame<3>(D);
      EXPECT_EQ(D, fiber_frame_at<3>(f, Vec3d::Ones(), uint64_t(k)));
      const Vec3d a = D.col(0).cast<double>();
      const double t3 = std::acos(std::clamp(a.dot(f.a1), -1.0, 1.0));
      EXPECT_LE(t3, bound + 1e-9);
      largest3 = std::max(largest3, t3);
      mean3 += a - a.dot(f.a1) * f.a1;
      FiberSpec f2 = f;
      f2.a1 = Vec3d(1, 2, 0).normalized();
      const Vec<2> b = fiber_frame_at<2>(f2, Vec3d::Zero(), uint64_t(k)).col(0);
      const double t2 = std::atan2(f2.a1.x() * b.y() - f2.a1.y() * b.x(),
                                   f2.a1.x() * b.x() + f2.a1.y() * b.y());
      EXPECT_LE(std::abs(t2), bound + 1e-9);
      largest2 = std::max(largest2, t2);
      smallest2 = std::min(smallest2, t2);
    }
    EXPECT_GT(largest3, 0.95 * bound);
    EXPECT_GT(largest2, 0.95 * bound);
    EXPECT_LT(smallest2, -0.95 * bound);
    EXPECT_LT((mean3 / n).norm(), 0.05 * bound);  // no preferred side
  }
}

TEST(FiberFrame, SampledTubeHasCircumferentialFibers) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {{"shape",
                        {{"type", "tube"},
                         {"center", {0.5, 0.5, 0.5}},
                         {"axis", {0, 0, 1}},
                         {"radius", 0.3},
                         {"inner_radius", 0.2},
                         {"height", 0.4}}},
                       {"material", "jelly"},
                       {"fibers", {{"type", "circumferential"}}}};
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

// --- particle counts: ppc * volume / dx^dim for every shape, 2D and 3D -----------------------

struct CountCase {
  const char* name;
  int dim;
  const char* shape;  // JSON of the shape (inside the unit domain)
  double volume;      // exact area (2D) or volume (3D)
};

const CountCase kCountCases[] = {
    {"Box2D", 2, R"({"type": "box", "min": [0.23, 0.31], "max": [0.71, 0.62]})", 0.48 * 0.31},
    {"Disk2D", 2, R"({"type": "sphere", "center": [0.5, 0.5], "radius": 0.3})", kPi * 0.09},
    // 2D cylinder: a rectangle 2R wide, h long along the (tilted) axis.
    {"Cylinder2D", 2,
     R"({"type": "cylinder", "center": [0.5, 0.5], "axis": [1, 1], "radius": 0.1, "height": 0.6})",
     0.2 * 0.6},
    {"Tube2D", 2,
     R"({"type": "tube", "center": [0.5, 0.5], "axis": [1, 2], "radius": 0.2, "inner_radius": 0.1,
         "height": 0.5})",
     2 * 0.1 * 0.5},
    {"Box3D", 3, R"({"type": "box", "min": [0.2, 0.3, 0.25], "max": [0.7, 0.6, 0.75]})",
     0.5 * 0.3 * 0.5},
    {"Sphere3D", 3, R"({"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.3})",
     4.0 / 3 * kPi * 0.027},
    {"Cylinder3D", 3,
     R"({"type": "cylinder", "center": [0.5, 0.5, 0.5], "axis": [1, 1, 1], "radius": 0.15,
         "height": 0.5})",
     kPi * 0.0225 * 0.5},
    {"Tube3D", 3,
     R"({"type": "tube", "center": [0, 0, 0], "axis": [0, 1, 0], "radius": 0.25,
         "inner_radius": 0.15, "height": 0.5,
         "transform": {"rotate": {"axis": [1, 0, 0], "angle_deg": 30},
                       "translate": [0.5, 0.5, 0.5]}})",
     kPi * (0.0625 - 0.0225) * 0.5},
};

json count_scene(const CountCase& c, int ppc, const std::string& sampling, int seed = 1) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = c.dim;
  doc["seed"] = seed;
  if (c.dim == 3)
    doc["grid"] = {{"dx", 0.02}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  else
    doc["grid"]["dx"] = 0.01;
  doc["objects"][0] = {{"shape", json::parse(c.shape)}, {"material", "jelly"}, {"ppc", ppc},
                       {"sampling", sampling}};
  return doc;
}

template <int Dim>
void check_count(const CountCase& c, int ppc, const std::string& sampling, double tol) {
  Scene s = parse_scene(count_scene(c, ppc, sampling), "count.json");
  Particles<Dim> p = sample_scene<Dim>(s);
  const double expected = ppc * c.volume / std::pow(s.dx, Dim);
  EXPECT_NEAR(p.size() / expected, 1, tol)
      << c.name << " ppc " << ppc << " " << sampling << ": " << p.size() << " vs " << expected;
  double mass = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    Vec3d x = Vec3d::Zero();
    x.head<Dim>() = p.x[i].template cast<double>();
    ASSERT_LE(s.objects[0].shape.sdf(x), 0) << c.name << " " << x.transpose();
    mass += p.mass[i];
  }
  // Total mass approximates rho * volume the same way.
  EXPECT_NEAR(mass / (2 * c.volume), 1, tol) << c.name;
}

TEST(SamplingCount, MatchesPpcTimesVolumeOverCellVolume) {
  for (const CountCase& c : kCountCases) {
    SCOPED_TRACE(c.name);
    const int k = c.dim == 2 ? 4 : 8;  // stratified 2^dim, plain uniform, and lattice
    for (int ppc : {k, k + 1}) {
      if (c.dim == 2)
        check_count<2>(c, ppc, "random", 0.02);
      else
        check_count<3>(c, ppc, "random", 0.02);
    }
    if (c.dim == 2)
      check_count<2>(c, k, "grid", 0.02);
    else
      check_count<3>(c, k, "grid", 0.02);
  }
}

// Grid sampling puts exactly one particle at every sub-cell centre (domain_min + (i + 1/2)
// dx / k) inside the shape: for a box aligned with the sub-cells that is the full lattice.
TEST(SamplingGrid, ExactLattice3D) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.1}, {"domain_min", {-1, -1, -1}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {
      {"shape", {{"type", "box"}, {"min", {-0.2, 0.0, 0.3}}, {"max", {0.2, 0.3, 0.5}}}},
      {"material", "jelly"},
      {"ppc", 27},
      {"sampling", "grid"}};
  Particles<3> p = sample_scene<3>(parse_scene(doc, "lattice.json"));
  const double h = 0.1 / 3;
  // 12 x 9 x 6 sub-cells of size h.
  ASSERT_EQ(p.size(), 12u * 9u * 6u);
  std::set<std::array<long, 3>> seen;
  for (size_t i = 0; i < p.size(); ++i) {
    std::array<long, 3> idx;
    for (int d = 0; d < 3; ++d) {
      double k = (p.x[i][d] + 1) / h - 0.5;  // lattice index from domain_min
      EXPECT_NEAR(k, std::round(k), 1e-9);
      idx[d] = std::lround(k);
    }
    const long lo[3] = {24, 30, 39}, hi[3] = {36, 39, 45};
    for (int d = 0; d < 3; ++d) {
      EXPECT_GE(idx[d], lo[d]);
      EXPECT_LT(idx[d], hi[d]);
    }
    EXPECT_TRUE(seen.insert(idx).second) << "duplicate lattice point";
    EXPECT_EQ(p.fiber_of(i), Mat<3>::Identity());  // default fibers: a1 = x, a2 = y
  }
  // Every frame the identity: the field is off (72 bytes a particle in no reorder).
  EXPECT_FALSE(p.enabled("fiber"));
  EXPECT_TRUE(p.fiber.empty());
}

TEST(SamplingGrid, DoesNotDependOnSeed) {
  json doc = test::minimal_scene_2d();
  doc["objects"][0]["sampling"] = "grid";
  Particles<2> a = sample_scene<2>(parse_scene(doc, "a.json"));
  doc["seed"] = 99;
  Particles<2> b = sample_scene<2>(parse_scene(doc, "b.json"));
  EXPECT_TRUE(same_bits(a, b));
}

TEST(Sampling, DeterministicFromSeed3DWithRandomFibers) {
  auto sample = [](int seed) {
    json doc = count_scene(kCountCases[5], 8, "random", seed);  // the 3D sphere
    doc["grid"]["dx"] = 0.05;
    doc["objects"][0]["fibers"] = {{"type", "random"}};
    return sample_scene<3>(parse_scene(doc, "ball.json"));
  };
  Particles<3> a = sample(5), b = sample(5), c = sample(6);
  EXPECT_TRUE(same_bits(a, b));
  EXPECT_FALSE(same_bits(a, c));
  size_t n = std::min(a.size(), c.size()), differ = 0;
  for (size_t i = 0; i < n; ++i) differ += a.fiber[i] != c.fiber[i];
  EXPECT_GT(differ, n / 2);
}

// --- fiber fields on sampled objects: unit, pointing the documented way, proper frames -------

// The documented frame of each field at world point x (SCENE_FORMAT.md, scene_reference.md).
struct FieldCheck {
  const char* type;
  // Expected a1 (and, in 3D, a2 when non-zero) at x, given the field's centre and unit axis.
  std::function<void(const Vec3d& x, const Vec3d& c, const Vec3d& axis, Vec3d* a1, Vec3d* a2)> f;
};

Vec3d radial_from_axis(const Vec3d& x, const Vec3d& c, const Vec3d& axis) {
  Vec3d d = x - c;
  return (d - d.dot(axis) * axis).normalized();
}

const FieldCheck kFields3D[] = {
    {"radial",
     [](const Vec3d& x, const Vec3d& c, const Vec3d& ax, Vec3d* a1, Vec3d* a2) {
       *a1 = radial_from_axis(x, c, ax);  // away from the axis through the centre
       *a2 = ax;
     }},
    {"circumferential",
     [](const Vec3d& x, const Vec3d& c, const Vec3d& ax, Vec3d* a1, Vec3d* a2) {
       *a1 = ax.cross(radial_from_axis(x, c, ax));  // tangent, counter-clockwise about axis
       *a2 = ax;
     }},
    {"longitudinal",
     [](const Vec3d& x, const Vec3d& c, const Vec3d& ax, Vec3d* a1, Vec3d* a2) {
       *a1 = ax;
       *a2 = radial_from_axis(x, c, ax);
     }},
};

template <int Dim>
void expect_frame_of_field(const Mat<Dim>& D, const Vec3d& a1, const Vec3d& a2) {
  Vec3d got1 = Vec3d::Zero(), got2 = Vec3d::Zero();
  got1.head<Dim>() = D.col(0).template cast<double>();
  got2.head<Dim>() = D.col(1).template cast<double>();
  EXPECT_NEAR(got1.norm(), 1, 1e-12);
  EXPECT_NEAR((got1 - a1).norm(), 0, 1e-9) << got1.transpose() << " vs " << a1.transpose();
  if (a2.norm() > 0) {
    EXPECT_NEAR((got2 - a2).norm(), 0, 1e-9);
  }
  EXPECT_NEAR(got1.dot(got2), 0, 1e-12);
  expect_proper_frame<Dim>(D, 1e-12);
  if constexpr (Dim == 2) {
    EXPECT_EQ(D(0, 1), -D(1, 0));  // a2 = (-a1.y, a1.x): a1 turned 90 degrees
    EXPECT_EQ(D(1, 1), D(0, 0));
  } else {
    EXPECT_NEAR((D.col(2) - D.col(0).cross(D.col(1))).norm(), 0, 1e-12);
  }
}

TEST(FiberField, SampledTiltedTube3DFollowsEveryField) {
  // A tube about the axis (1, 2, 2)/3 (given as a rotated y axis would be harder to read):
  // its fibers default to that axis and the tube's centre.
  const Vec3d axis = Vec3d(1, 2, 2) / 3, centre(0.5, 0.5, 0.5);
  for (const FieldCheck& field : kFields3D) {
    SCOPED_TRACE(field.type);
    json doc = test::minimal_scene_2d();
    doc["dim"] = 3;
    doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
    doc["objects"][0] = {{"shape",
                          {{"type", "tube"},
                           {"center", {0.5, 0.5, 0.5}},
                           {"axis", {1, 2, 2}},
                           {"radius", 0.3},
                           {"inner_radius", 0.15},
                           {"height", 0.4}}},
                         {"material", "jelly"},
                         {"fibers", {{"type", field.type}}}};
    Scene s = parse_scene(doc, "tube.json");
    EXPECT_NEAR((s.objects[0].fibers.axis - axis).norm(), 0, 1e-15);
    Particles<3> p = sample_scene<3>(s);
    ASSERT_GT(p.size(), 1000u);
    for (size_t i = 0; i < p.size(); ++i) {
      Vec3d a1, a2;
      field.f(p.x[i].cast<double>(), centre, axis, &a1, &a2);
      expect_frame_of_field<3>(p.fiber[i], a1, a2);
    }
  }
}

TEST(FiberField, SampledConstantAndRandom3D) {
  json doc = test::minimal_scene_2d();
  doc["dim"] = 3;
  doc["grid"] = {{"dx", 0.05}, {"domain_min", {0, 0, 0}}, {"domain_max", {1, 1, 1}}};
  doc["objects"][0] = {
      {"shape", {{"type", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.3}}},
      {"material", "jelly"},
      {"fibers", {{"type", "constant"}, {"a1", {0, 0, 2}}, {"a2", {1, 0, 1}}}}};
  Particles<3> p = sample_scene<3>(parse_scene(doc, "c.json"));
  ASSERT_GT(p.size(), 0u);
  for (size_t i = 0; i < p.size(); ++i)  // a1 normalised, a2 made orthogonal to it
    expect_frame_of_field<3>(p.fiber[i], Vec3d::UnitZ(), Vec3d::UnitX());
  doc["objects"][0]["fibers"] = {{"type", "random"}};
  p = sample_scene<3>(parse_scene(doc, "r.json"));
  for (size_t i = 0; i < p.size(); ++i)
    expect_frame_of_field<3>(p.fiber[i], p.fiber[i].col(0).cast<double>(), Vec3d::Zero());
}

TEST(FiberField, SampledDiskAndStrips2DFollowEveryField) {
  const Vec3d c(0.45, 0.55, 0);
  json doc = test::minimal_scene_2d();
  doc["grid"]["dx"] = 0.02;
  doc["objects"][0] = {{"shape", {{"type", "sphere"}, {"center", {0.45, 0.55}}, {"radius", 0.3}}},
                       {"material", "jelly"}, {"fibers", {{"type", "radial"}}}};
  Particles<2> radial = sample_scene<2>(parse_scene(doc, "r.json"));
  doc["objects"][0]["fibers"]["type"] = "circumferential";
  Particles<2> circ = sample_scene<2>(parse_scene(doc, "c.json"));
  ASSERT_EQ(radial.size(), circ.size());
  ASSERT_GT(radial.size(), 0u);
  for (size_t i = 0; i < radial.size(); ++i) {
    Vec3d r(radial.x[i].x() - c.x(), radial.x[i].y() - c.y(), 0);
    r.normalize();
    expect_frame_of_field<2>(radial.fiber[i], r, Vec3d(-r.y(), r.x(), 0));
    expect_frame_of_field<2>(circ.fiber[i], Vec3d(-r.y(), r.x(), 0), Vec3d(-r.x(), -r.y(), 0));
  }
  // Longitudinal along a 2D tube's axis (two strips), and constant a1 normalised.
  doc["objects"][0]["shape"] = {{"type", "tube"}, {"center", {0.5, 0.5}}, {"axis", {3, 4}},
                                {"radius", 0.2}, {"inner_radius", 0.1}, {"height", 0.5}};
  doc["objects"][0]["fibers"] = {{"type", "longitudinal"}};
  Particles<2> lon = sample_scene<2>(parse_scene(doc, "l.json"));
  ASSERT_GT(lon.size(), 0u);
  for (size_t i = 0; i < lon.size(); ++i)
    expect_frame_of_field<2>(lon.fiber[i], Vec3d(0.6, 0.8, 0), Vec3d(-0.8, 0.6, 0));
  doc["objects"][0]["fibers"] = {{"type", "constant"}, {"a1", {-2, 0}}};
  Particles<2> con = sample_scene<2>(parse_scene(doc, "k.json"));
  for (size_t i = 0; i < con.size(); ++i)
    expect_frame_of_field<2>(con.fiber[i], Vec3d(-1, 0, 0), Vec3d(0, -1, 0));
}

}  // namespace
}  // namespace tear
