// Crack angle (AnisoMPM Fig. 10-12) from a notch cut by geometry: a tall block gripped top and
// bottom and pulled apart tears along its fibers when they are at +-45 degrees (alpha = -1)
// and straight across the pull when it is isotropic. The angle is the principal axis of the
// rest positions of the cracked particles (d > 0.5, unweighted) connected to the slit tip.
#include "mpm_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace tear {
namespace {
using testing::MpmSim;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDx = 1.0 / 64;
constexpr double kSlitTipX = 0.38;

// A 0.4 x 0.6 block [0.3, 0.7] x [0.2, 0.8] with a slit 2 cells tall from its left edge to
// x = 0.38, centred on y = 0.5. The three boxes meet on cell faces, so the sampling lattice
// (particles at (j + 1/2) dx / 2) puts no particle twice and the scene is mirror-symmetric
// about y = 0.5. The grips are as wide as the block and hold its top and bottom 0.04; the
// block is tall enough that a 45-degree crack from the slit reaches the right edge below the
// top grip. Fibers at `fiber_degrees` with alpha = -1 and fiber stiffness 20 mu, or no fibers
// and alpha = 0 when `isotropic`.
// With `implicit_integrator`, backward Euler steps of up to `max_dt` (else symplectic Euler).
Scene slit_block(const std::string& solver, double fiber_degrees, bool isotropic,
                 bool implicit_integrator = false, double max_dt = 5e-4) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "dim": 2, "grid": { "dx": 0.015625, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.05, "frames": 1, "max_dt": 5e-4 },
    "damage": { "solver": "explicit" },
    "materials": {
      "m": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2,
             "damage": { "sigma_c": 8, "eta": 0.05, "residual": 0.001, "alpha": 0 } } },
    "objects": [
      { "shape": { "type": "box", "min": [0.3, 0.2], "max": [0.38, 0.484375] },
        "material": "m", "sampling": "grid", "ppc": 4 },
      { "shape": { "type": "box", "min": [0.3, 0.515625], "max": [0.38, 0.8] },
        "material": "m", "sampling": "grid", "ppc": 4 },
      { "shape": { "type": "box", "min": [0.38, 0.2], "max": [0.7, 0.8] },
        "material": "m", "sampling": "grid", "ppc": 4 } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.3, 0.76], "max": [0.7, 0.85] },
        "velocity": [0, 0.15] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.3, 0.15], "max": [0.7, 0.24] },
        "velocity": [0, -0.15] } ]
  })");
  doc["damage"]["solver"] = solver;
  doc["time"]["max_dt"] = max_dt;
  if (implicit_integrator) doc["integrator"] = "implicit";
  if (!isotropic) {
    const double t = fiber_degrees * kPi / 180;
    nlohmann::json& m = doc["materials"]["m"];
    m["fiber_scale"] = {20};
    m["damage"]["alpha"] = -1;
    for (nlohmann::json& o : doc["objects"])
      o["fibers"] = {{"type", "constant"}, {"a1", {std::cos(t), std::sin(t)}}};
  }
  return parse_scene(doc, "slit_block.json");
}

struct Crack {
  double angle_degrees = 0;  // principal axis of the crack's particles, in (-90, 90]
  double aspect = 0;         // sqrt of the principal variances' ratio: > 1 when elongated
  double length = 0;         // sqrt(12 var) along the axis: the length of a uniform line
  size_t cracked = 0;        // particles in the crack
};

// The crack grown from the slit: particles with d > 0.5 connected, through rest-lattice
// neighbours (spacing dx / 2, diagonals dx / 2 sqrt 2), to cracked particles at the slit tip.
// Cracks that start elsewhere (at the grips' corners) are left out.
std::vector<char> crack_from_slit_tip(const std::vector<Vec<2>>& rest,
                                      const std::vector<Real>& damage) {
  const size_t n = rest.size();
  const Real reach = Real(0.75 * kDx);
  std::vector<char> in(n, 0);
  std::vector<size_t> front;
  for (size_t i = 0; i < n; ++i)
    if (damage[i] > 0.5 && rest[i][0] < kSlitTipX + kDx && std::abs(rest[i][1] - 0.5) < 2 * kDx)
      in[i] = 1, front.push_back(i);
  while (!front.empty()) {
    const size_t i = front.back();
    front.pop_back();
    for (size_t j = 0; j < n; ++j)
      if (!in[j] && damage[j] > 0.5 && (rest[j] - rest[i]).norm() < reach)
        in[j] = 1, front.push_back(j);
  }
  return in;
}

// Principal axis of the points X[i] with in[i] set.
Crack principal_axis(const std::vector<Vec<2>>& X, const std::vector<char>& in) {
  Crack c;
  Vec<2> mean = Vec<2>::Zero();
  for (size_t i = 0; i < X.size(); ++i)
    if (in[i]) mean += X[i], ++c.cracked;
  if (c.cracked < 3) return c;
  mean /= Real(c.cracked);
  double sxx = 0, syy = 0, sxy = 0;
  for (size_t i = 0; i < X.size(); ++i)
    if (in[i]) {
      const Vec<2> r = X[i] - mean;
      sxx += r[0] * r[0], syy += r[1] * r[1], sxy += r[0] * r[1];
    }
  c.angle_degrees = 0.5 * std::atan2(2 * sxy, sxx - syy) * 180 / kPi;
  const double m = (sxx + syy) / 2, r = std::hypot((sxx - syy) / 2, sxy);
  c.aspect = std::sqrt((m + r) / std::max(m - r, 1e-30));
  c.length = std::sqrt(12 * (m + r) / double(c.cracked));
  return c;
}

// Pulls the slit block apart for 0.3 s with the given damage solver ("explicit" or
// "implicit"), checking after every step that each particle's damage (tracked by id: the
// solver reorders particles) never decreases and stays in [0, 1]. By then the crack has
// crossed the block. It is measured in rest positions (material space).
Crack tear_slit_block(const std::string& solver, double fiber_degrees, bool isotropic,
                      bool implicit_integrator = false, double max_dt = 5e-4) {
  constexpr double kTime = 0.3;
  MpmSim<2> sim(slit_block(solver, fiber_degrees, isotropic, implicit_integrator, max_dt));
  const Particles<2>& p = sim.particles();
  const size_t n = p.size();
  std::vector<Real> damage(n, 0);  // by id
  std::vector<Vec<2>> rest(n);
  for (size_t i = 0; i < n; ++i) rest[p.id[i]] = p.x[i];
  while (sim.time() < kTime) {
    sim.step(std::min(sim.estimate_dt(), kTime - sim.time() + 1e-12));
    for (size_t i = 0; i < n; ++i) {
      const uint32_t id = p.id[i];
      EXPECT_GE(p.damage[i], damage[id]) << "damage decreased, particle " << id;
      EXPECT_GE(p.damage[i], 0);
      EXPECT_LE(p.damage[i], 1);
      damage[id] = p.damage[i];
    }
    if (::testing::Test::HasFailure()) return {};
  }
  return principal_axis(rest, crack_from_slit_tip(rest, damage));
}

// Asserts a crack across the block at `degrees` (within 10); records the measured figures
// (--gtest_output=xml shows them).
void expect_crack_at(const Crack& c, double degrees, const std::string& label) {
  ::testing::Test::RecordProperty(label + "_angle_degrees", std::to_string(c.angle_degrees));
  ::testing::Test::RecordProperty(label + "_cracked", std::to_string(c.cracked));
  ::testing::Test::RecordProperty(label + "_aspect", std::to_string(c.aspect));
  ::testing::Test::RecordProperty(label + "_length", std::to_string(c.length));
  std::printf("  %s: %.1f degrees, %zu particles, aspect %.2f, length %.3f\n", label.c_str(),
              c.angle_degrees, c.cracked, c.aspect, c.length);
  // From the slit tip at x = 0.38 to the block's right edge is 0.32, to a grip 0.24.
  EXPECT_GT(c.length, 0.22) << label << ": no crack across the block";
  // A blob has aspect ~1; the band of a crack across the block, > 2.5 (the isotropic band
  // is widest: explicit 5.3, and the implicit solver's wider band 2.75 when last measured).
  EXPECT_GT(c.aspect, 2.5) << label << ": the damage is a blob, not a line";
  // Axes are undirected: compare modulo 180 degrees.
  EXPECT_NEAR(std::remainder(c.angle_degrees - degrees, 180.0), 0, 10)
      << label << ": " << c.angle_degrees << " degrees";
}

void expect_cracks_follow_diagonal_fibers(const std::string& solver) {
  // The scene is symmetric under y -> 1 - y, which maps fibers at 45 to -45 degrees.
  const Crack up = tear_slit_block(solver, 45, false);
  const Crack down = tear_slit_block(solver, -45, false);
  expect_crack_at(up, 45, solver + "_fibers_45");
  expect_crack_at(down, -45, solver + "_fibers_-45");
  EXPECT_NEAR(down.angle_degrees, -up.angle_degrees, 1) << solver;
}

void expect_isotropic_crack_runs_straight(const std::string& solver) {
  expect_crack_at(tear_slit_block(solver, 0, true), 0, solver + "_isotropic");
}

// Measured (dx = 1/64; implicit within 0.1 degree and 2 particles of explicit): 45-degree
// fibers 42.9 degrees (345 particles, aspect 8.1); -45-degree fibers -42.9; isotropic 0.0
// (260 particles, aspect 5.3). The crack leaves the slit a little flatter than the fibers, as
// the mode-I load pulls it straight ahead.

TEST(CrackAngle, FollowsFibersAtPlusAndMinusFortyFiveDegreesExplicit) {
  expect_cracks_follow_diagonal_fibers("explicit");
}
TEST(CrackAngle, RunsStraightAcrossThePullWhenIsotropicExplicit) {
  expect_isotropic_crack_runs_straight("explicit");
}
TEST(CrackAngle, FollowsFibersAtPlusAndMinusFortyFiveDegreesImplicit) {
  expect_cracks_follow_diagonal_fibers("implicit");
}
TEST(CrackAngle, RunsStraightAcrossThePullWhenIsotropicImplicit) {
  expect_isotropic_crack_runs_straight("implicit");
}

// The implicit integrator at 2e-3, about 7x the explicit step limit (3e-4), with either damage
// solver: the crack still follows the fibers.
TEST(CrackAngle, FollowsFibersUnderTheImplicitIntegrator) {
  for (const char* solver : {"explicit", "implicit"}) {
    const Crack up = tear_slit_block(solver, 45, false, true, 2e-3);
    const Crack down = tear_slit_block(solver, -45, false, true, 2e-3);
    expect_crack_at(up, 45, std::string("implicit_integrator_") + solver + "_fibers_45");
    expect_crack_at(down, -45, std::string("implicit_integrator_") + solver + "_fibers_-45");
  }
}

TEST(CrackAngle, FollowsFibersAcrossAndAlongThePull) {
  // alpha = -1: tension along the fibers does not drive damage, tension across them does, so
  // the crack runs along the fibers even when they lie along the pull: the block splits
  // lengthwise from the slit tip (string cheese). Measured, both solvers: 0 degrees (246
  // particles, length 0.28) and 90 degrees (110 particles, aspect 26, length 0.42).
  for (const char* solver : {"explicit", "implicit"}) {
    const Crack a = tear_slit_block(solver, 0, false), b = tear_slit_block(solver, 90, false);
    expect_crack_at(a, 0, std::string(solver) + "_fibers_0");
    expect_crack_at(b, 90, std::string(solver) + "_fibers_90");
  }
}

TEST(CrackAngle, ThirtyDegreeFibersTiltTheCrackTowardsThem) {
  // With fibers at +-30 degrees the crack leaves the slit tilted towards them but flatter:
  // alpha = -1 removes tension along the fibers from the driving force, yet nothing in
  // AnisoMPM's model steers a crack onto the fibers once tension across them drives it
  // everywhere (the load is 75 % across 30-degree fibers), so the mode-I direction (0)
  // pulls it down. Measured: +-12.2 degrees, both solvers.
  for (const char* solver : {"explicit", "implicit"}) {
    const Crack up = tear_slit_block(solver, 30, false);
    const Crack down = tear_slit_block(solver, -30, false);
    std::printf("  %s: fibers +30 -> %.1f degrees, -30 -> %.1f\n", solver, up.angle_degrees,
                down.angle_degrees);
    EXPECT_GT(up.length, 0.22) << solver;
    EXPECT_GT(up.angle_degrees, 5) << solver;
    EXPECT_LT(up.angle_degrees, 30) << solver;
    EXPECT_NEAR(down.angle_degrees, -up.angle_degrees, 1) << solver;
  }
}

}  // namespace
}  // namespace tear
