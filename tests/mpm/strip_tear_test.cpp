// A fibered strip torn by two grips (issue 12's scene, stratified-random sampling): the two
// damage solvers agree for every mobility, the crack follows 60-degree fibers and runs across
// the pull when the strip is isotropic, and with l0 resolved by the grid the result converges
// as dt and dx shrink. And a 3D tube whose bands stay sharp. Crack figures are measured in
// rest space (damage/crack_metrics.h).
#include "tear/damage/crack_metrics.h"
#include "mpm_test_util.h"
#include "strip_scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace tear {
namespace {
using testing::MpmSim;

constexpr double kPi = 3.14159265358979323846;

using testing::isotropic_strip;
using testing::strip;

nlohmann::json with(nlohmann::json doc, const std::string& solver, double eta) {
  doc["damage"]["solver"] = solver;
  doc["materials"]["m"]["damage"]["eta"] = eta;
  return doc;
}

// Crack figures of a scene at each of `frames` (ascending), measured in rest space; with
// `cracked`, the rest positions of the cracked particles at the last frame. Checks after every
// step that damage (tracked by id) never decreases and stays in [0, 1].
template <int Dim>
std::vector<CrackFigures> tear(const Scene& scene, std::vector<int> frames,
                               const std::string& label, std::vector<Vec3d>* cracked = nullptr) {
  MpmSim<Dim> sim(scene);
  const Particles<Dim>& p = sim.particles();
  const size_t n = p.size();
  std::vector<Vec3d> rest(n, Vec3d::Zero());
  std::vector<double> damage(n, 0);
  for (size_t i = 0; i < n; ++i)
    rest[p.id[i]].template head<Dim>() = p.x[i].template cast<double>();
  const double spacing = particle_spacing(scene);
  std::vector<CrackFigures> out;
  bool monotone = true;
  for (int frame : frames) {
    const double end = frame * scene.frame_dt;
    while (sim.time() < end * (1 - 1e-12)) {
      sim.step(std::min(sim.estimate_dt(), end - sim.time()));
      for (size_t i = 0; i < n; ++i) {
        const double d = p.damage[i];
        monotone = monotone && d >= damage[p.id[i]] && d <= 1;
        damage[p.id[i]] = d;
      }
    }
    out.push_back(measure_cracks(Dim, rest, damage, spacing));
    const CrackFigures& c = out.back();
    std::printf(
        "  %s, frame %d: cracked %.3f, crack at %.1f degrees, normal (%.2f, %.2f, %.2f), "
        "width %.2f spacings\n",
        label.c_str(), frame, c.fraction, c.angle_degrees, c.normal[0], c.normal[1], c.normal[2],
        c.width_spacings);
  }
  EXPECT_TRUE(monotone) << label << ": damage decreased or left [0, 1]";
  if (cracked) {
    cracked->clear();
    for (size_t i = 0; i < n; ++i)
      if (damage[i] > 0.5) cracked->push_back(rest[i]);
  }
  return out;
}

std::vector<CrackFigures> tear_strip(const nlohmann::json& doc, std::vector<int> frames,
                                     const std::string& label,
                                     std::vector<Vec3d>* cracked = nullptr) {
  return tear<2>(parse_scene(doc, "strip.json"), frames, label, cracked);
}

// Angles of undirected lines: the difference modulo 180 degrees.
double angle_between(double a, double b) { return std::abs(std::remainder(a - b, 180.0)); }

void expect_solvers_agree(const CrackFigures& e, const CrackFigures& i, const std::string& what) {
  ASSERT_GT(e.fraction, 0.02) << what << ": the strip did not crack";
  EXPECT_NEAR(i.fraction / e.fraction, 1, 0.2) << what;
  EXPECT_LT(angle_between(e.angle_degrees, i.angle_degrees), 5) << what;
}

TEST(StripTear, SolversAgreeAndFollowSixtyDegreeFibers) {
  // Measured at frame 20: explicit 22.3 % cracked at 52.8 degrees, implicit 22.3 % at 52.5
  // (before, the grid-based implicit solver had cracked 65 % of the strip by then).
  const CrackFigures e = tear_strip(with(strip(60), "explicit", 0.02), {20}, "explicit").back();
  const CrackFigures i = tear_strip(with(strip(60), "implicit", 0.02), {20}, "implicit").back();
  expect_solvers_agree(e, i, "eta 0.02");
  EXPECT_LT(angle_between(e.angle_degrees, 60), 10);
  EXPECT_LT(angle_between(i.angle_degrees, 60), 10);
}

TEST(StripTear, AnisotropicCrackSurfaceSteersCracksOntoThirtyDegreeFibers) {
  // With the paper's isotropic surface term nothing steers a running crack onto fibers at 30
  // degrees to the crack the load would make (the strip cracks at the grips, across the pull;
  // from a notch at 14-20 degrees). damage.surface_anisotropy makes damage gradients along the
  // fiber cost more: from the notch the crack runs along the fibers. Measured at frame 10:
  // beta 0: 14.0 degrees; beta 30: explicit and implicit 22.2, 4.4 % cracked; mirrored fibers
  // (-30, seed 3) -23.0.
  auto notched = [](double degrees, double beta, const std::string& solver) {
    nlohmann::json doc = with(testing::notched_strip(degrees), solver, 0.02);
    doc["materials"]["m"]["damage"]["surface_anisotropy"] = beta;
    return doc;
  };
  const CrackFigures paper = tear_strip(notched(30, 0, "explicit"), {10}, "beta 0").back();
  const CrackFigures e = tear_strip(notched(30, 30, "explicit"), {10}, "explicit").back();
  const CrackFigures i = tear_strip(notched(30, 30, "implicit"), {10}, "implicit").back();
  expect_solvers_agree(e, i, "beta 30");
  EXPECT_LT(angle_between(e.angle_degrees, 30), 10);
  EXPECT_LT(angle_between(i.angle_degrees, 30), 10);
  EXPECT_LT(angle_between(e.angle_degrees, 30), angle_between(paper.angle_degrees, 30));
  nlohmann::json mirrored = notched(-30, 30, "explicit");
  mirrored["seed"] = 3;
  const CrackFigures m = tear_strip(mirrored, {10}, "explicit, -30 degrees, seed 3").back();
  EXPECT_LT(angle_between(m.angle_degrees, -30), 10);
}

// A strip or slab scene with the sharp-crack recipe of docs/materials.md: crack fields and
// surface_anisotropy 100, with the sampling `seed` and the damage `solver`.
nlohmann::json sharp_cracks(nlohmann::json doc, int seed, const std::string& solver) {
  doc = with(std::move(doc), solver, 0.02);
  doc["seed"] = seed;
  doc["damage"]["split_fields"] = true;
  doc["materials"]["m"]["damage"]["surface_anisotropy"] = 100;
  return doc;
}

// A torn band at two frames that stays sharp: at most 4 spacings wide at the first and no more
// than half a spacing wider at the second. Widths are medians of run lengths, in half spacings
// (up to rounding); one half spacing is the metric's own step.
void expect_sharp_band(const std::vector<CrackFigures>& c, const std::string& what) {
  ASSERT_GT(c[1].fraction, 0.02) << what << ": the strip did not crack";
  const auto halves = [](const CrackFigures& f) { return std::lround(2 * f.width_spacings); };
  EXPECT_LE(halves(c[0]), 8) << what << ": " << c[0].width_spacings << " spacings";
  EXPECT_LE(halves(c[1]), halves(c[0]) + 1) << what << ": the band widened";
}

TEST(StripTear, CrackFieldsWithAnisotropicSurfaceKeepSlidingCracksSharpAndOnTheFibers) {
  // The strip as the issue gives it (no notch), with crack fields (split_fields) and
  // surface_anisotropy 100 together: the crack surface steers the crack onto the fibers and the
  // second velocity field lets its faces slide apart without shearing the particles beside it.
  // Alone, crack fields let the first grip-corner crack set the path (34-51 degrees on 60-degree
  // fibers), and one velocity field shears the band to 7-7.5 spacings and wider.
  // Measured, 60 degrees at frames 20 / 30: explicit 56.8 degrees, 3.5 / 4.0 spacings, 7.0 /
  // 7.2 % cracked; implicit 56.8, 3.5 / 3.5, 7.4 / 7.6 %; seed 2 55.5, 3.5 / 3.5. 30 degrees
  // at frames 15 / 20 (bands only: seeds 1 and 3 follow the fibers at 27-28 degrees, seed 2 starts
  // at a grip's edge and ends at 10.5): seed 2 2.5 / 2.5 spacings, -30 degrees seed 3 2.5 / 2.5
  // (at -28.2 degrees). Without both: 7-7.5 spacings and growing; 30 degrees at 0.
  std::vector<CrackFigures> last;
  for (const char* solver : {"explicit", "implicit"}) {
    const std::string what = std::string("60 degrees, ") + solver + ", seed 1";
    const std::vector<CrackFigures> c = tear_strip(sharp_cracks(strip(60), 1, solver), {20, 30}, what);
    expect_sharp_band(c, what);
    EXPECT_LT(angle_between(c[1].angle_degrees, 60), 10) << what;
    last.push_back(c[1]);
  }
  expect_solvers_agree(last[0], last[1], "60 degrees, seed 1");
  expect_sharp_band(tear_strip(sharp_cracks(strip(30), 2, "explicit"), {15, 20}, "30 degrees, seed 2"),
                    "30 degrees, seed 2");
}

// The same with another seed at 60 degrees and mirrored fibers (-30 degrees, seed 3): two more
// strip runs, left to the study (ctest -L study) for CI's time.
TEST(StripTearStudy, CrackFieldsWithAnisotropicSurfaceKeepSlidingCracksSharpForOtherSeeds) {
  const std::string what = "60 degrees, explicit, seed 2";
  const std::vector<CrackFigures> c = tear_strip(sharp_cracks(strip(60), 2, "explicit"), {20, 30}, what);
  expect_sharp_band(c, what);
  EXPECT_LT(angle_between(c[1].angle_degrees, 60), 10) << what;
  expect_sharp_band(tear_strip(sharp_cracks(strip(-30), 3, "explicit"), {15, 20}, "-30 degrees, seed 3"),
                    "-30 degrees, seed 3");
}

TEST(StripTear, CrackFieldsWithAnisotropicSurfaceRunFromANotchAlongThirtyDegreeFibers) {
  // Where the crack should start is given (the notched strip), both extensions together put it
  // on 30-degree fibers within a degree or two and in a band two spacings wide (the surface
  // term alone: 22-24 degrees). Measured at frame 15: seed 2 explicit 32.0 degrees, 2.0
  // spacings, 1.4 % cracked; implicit 30.0, 2.5, 1.7 %; -30 degrees seed 3 -30.0, 1.5.
  auto notched = [](double degrees, int seed, const std::string& solver) {
    return sharp_cracks(testing::notched_strip(degrees), seed, solver);
  };
  for (const auto& [degrees, seed, solver] :
       {std::tuple<double, int, const char*>{30, 2, "explicit"},
        {30, 2, "implicit"},
        {-30, 3, "explicit"}}) {
    const std::string what =
        std::to_string(int(degrees)) + " degrees, seed " + std::to_string(seed) + ", " + solver;
    const CrackFigures c = tear_strip(notched(degrees, seed, solver), {15}, what).back();
    ASSERT_GT(c.fraction, 0.01) << what << ": the strip did not crack";
    EXPECT_LT(angle_between(c.angle_degrees, degrees), 5) << what;
    EXPECT_LE(c.width_spacings, 3 + 1e-9) << what;
  }
}

// The 3D slab 0.2 x 0.6 x 0.08 (dx 0.02, 8 particles per cell, stratified random) with fibers
// at `degrees` in the x-y plane and a2 along z, pulled along y by sticky grips; `notched`: with
// the slit [0.4, 0.44] x [0.5, 0.52] through the thickness (three boxes).
nlohmann::json slab(double degrees, bool notched) {
  const double t = degrees * kPi / 180;
  nlohmann::json doc = nlohmann::json::parse(R"({
    "dim": 3, "seed": 1,
    "grid": { "dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "separate" },
    "time": { "frame_dt": 0.02, "frames": 1, "max_dt": 2e-4 },
    "damage": { "solver": "explicit" },
    "materials": {
      "m": { "model": "qr_aniso", "E": 2000, "nu": 0.3, "rho": 1, "fiber_scale": [10, 0],
             "damage": { "sigma_c": 60, "eta": 0.02, "residual": 0.001, "alpha": -1 } } },
    "objects": [],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.35, 0.76, 0.4], "max": [0.65, 0.85, 0.6] },
        "velocity": [0, 0.05, 0] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.35, 0.15, 0.4], "max": [0.65, 0.24, 0.6] },
        "velocity": [0, -0.05, 0] } ]
  })");
  std::vector<std::pair<Vec3d, Vec3d>> boxes = {{{0.4, 0.2, 0.46}, {0.6, 0.8, 0.54}}};
  if (notched)
    boxes = {{{0.4, 0.2, 0.46}, {0.44, 0.5, 0.54}},
             {{0.4, 0.52, 0.46}, {0.44, 0.8, 0.54}},
             {{0.44, 0.2, 0.46}, {0.6, 0.8, 0.54}}};
  for (const auto& [lo, hi] : boxes)
    doc["objects"].push_back(
        {{"shape",
          {{"type", "box"}, {"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}}},
         {"material", "m"},
         {"ppc", 8},
         {"fibers",
          {{"type", "constant"}, {"a1", {std::cos(t), std::sin(t), 0}}, {"a2", {0, 0, 1}}}}});
  return doc;
}

// A crack plane's line in the x-y plane, from its normal, in (-90, 90] degrees.
double line_degrees(const CrackFigures& c) {
  return std::remainder(std::atan2(-c.normal.x(), c.normal.y()) * 180 / kPi, 180.0);
}

TEST(StripTear, AnisotropicCrackSurfaceSteersCracksOntoFibersIn3D) {
  // The notched slab with fibers at 30 degrees. Measured at frame 8 (crack line in the x-y
  // plane): beta 0: 3.4 degrees; beta 100: explicit 22.1, implicit 22.6, 7 % cracked; the crack
  // plane contains z (|n_z| <= 0.03).
  const nlohmann::json doc = slab(30, true);
  auto run = [&](const std::string& solver, double beta) {
    nlohmann::json d = doc;
    d["damage"]["solver"] = solver;
    d["materials"]["m"]["damage"]["surface_anisotropy"] = beta;
    const std::string label = solver + " beta " + std::to_string(int(beta));
    const CrackFigures c = tear<3>(parse_scene(d, "slab.json"), {8}, label).back();
    std::printf("  %s: crack line at %.1f degrees in the x-y plane\n", label.c_str(),
                line_degrees(c));
    EXPECT_GT(c.fraction, 0.03) << solver << " beta " << beta << ": the slab did not crack";
    EXPECT_LT(std::abs(c.normal.z()), 0.1) << solver << " beta " << beta;
    return c;
  };
  const CrackFigures paper = run("explicit", 0), e = run("explicit", 100), i = run("implicit", 100);
  EXPECT_LT(angle_between(line_degrees(e), 30), 10) << line_degrees(e);
  EXPECT_LT(angle_between(line_degrees(i), 30), 10) << line_degrees(i);
  EXPECT_NEAR(i.fraction / e.fraction, 1, 0.2);
  EXPECT_GT(angle_between(line_degrees(paper), 30), angle_between(line_degrees(e), 30) + 10)
      << line_degrees(paper);
}

// The 60-degree slab without a notch torn with crack fields and surface_anisotropy 100 by one
// damage solver: the crack runs along the fibers, its plane contains z, its band stays sharp.
void expect_sharp_slab(const char* solver) {
  const nlohmann::json doc = sharp_cracks(slab(60, false), 1, solver);
  const std::vector<CrackFigures> c = tear<3>(parse_scene(doc, "slab.json"), {14, 16}, solver);
  ASSERT_GT(c[1].fraction, 0.03) << solver << ": the slab did not crack";
  EXPECT_LT(angle_between(line_degrees(c[1]), 60), 10) << solver << ": " << line_degrees(c[1]);
  EXPECT_LT(std::abs(c[1].normal.z()), 0.1) << solver;
  EXPECT_LE(c[0].width_spacings, 4) << solver;
  EXPECT_LE(c[1].width_spacings, c[0].width_spacings + 0.5) << solver << ": the band widened";
}

TEST(StripTear, CrackFieldsWithAnisotropicSurfaceKeepSlidingCracksSharpIn3D) {
  // The slab without a notch, fibers at 60 degrees, crack fields and surface_anisotropy 100:
  // the crack runs along the fibers and its faces slide apart in a band that stops widening.
  // Measured at frames 14 / 16: explicit 61.9 degrees, 2.55 / 2.55 spacings, 8.2 / 8.5 %
  // cracked; implicit 59.8 degrees, 2.55 / 2.55, 9.2 / 9.6 %; |n_z| 0.08-0.09. The paper's (one
  // field, beta 0; `tear run` of the same scene): 40 degrees, 7.0 / 6.4 spacings, 24 / 28 %.
  expect_sharp_slab("explicit");
}

// The same slab with the implicit damage solver (the 2D strip tests compare the solvers in CI;
// this 3D run is left to the study for CI's time).
TEST(StripTearStudy, CrackFieldsWithAnisotropicSurfaceKeepSlidingCracksSharpIn3DImplicit) {
  expect_sharp_slab("implicit");
}

TEST(StripTear, SolversAgreeWhenCracksGrowSlowly) {
  // eta 1: damage lags the load; the first cracks come at frame ~20.
  const CrackFigures e = tear_strip(with(strip(60), "explicit", 1), {30}, "explicit").back();
  const CrackFigures i = tear_strip(with(strip(60), "implicit", 1), {30}, "implicit").back();
  expect_solvers_agree(e, i, "eta 1");
}

TEST(StripTear, ImplicitAtVanishingMobilityMatchesFastExplicitCracks) {
  // eta 1e-9 is instant cracking, beyond the explicit solver (its step would be 1e-11 s);
  // explicit damage at eta 0.002, already near the rate-independent limit, tears the same way.
  // Its steps need no hand-tuned max_dt: the damage limit (2e-5 s while cracks grow) sets them.
  nlohmann::json fast = with(strip(60), "explicit", 0.002);
  fast["time"]["max_dt"] = 1e-2;
  const CrackFigures e = tear_strip(fast, {20}, "explicit").back();
  const CrackFigures i = tear_strip(with(strip(60), "implicit", 1e-9), {20}, "implicit").back();
  expect_solvers_agree(e, i, "eta 0.002 vs 1e-9");
}

TEST(StripTear, IsotropicStripTearsAcrossThePullInSharpBands) {
  // Cracks start at the grips' edges and run straight across. Their bands stay within 4
  // particle spacings (the kinematic limit of the quadratic B-spline: a velocity jump between
  // two nodes strains particles over 2 dx), before and long after the pieces separated.
  for (const char* solver : {"explicit", "implicit"}) {
    const std::vector<CrackFigures> c =
        tear_strip(with(isotropic_strip(), solver, 0.02), {20, 40}, solver);
    ASSERT_GT(c[0].fraction, 0.05) << solver;
    EXPECT_LT(angle_between(c[1].angle_degrees, 0), 10) << solver;
    EXPECT_LE(c[0].width_spacings, 4) << solver;
    EXPECT_LE(c[1].width_spacings, 4) << solver;
  }
}

// The 60-degree strip torn with three max_dt's, each half the one before (2e-4 stands for
// 3.9e-5, the elastic limit, which then sets dt). At frame 9, while the crack grows from where
// it started, the cracked share must move by less at each halving; at frame 15, once its faces
// slide, how far the cracked set moves in rest space must shrink and stay under half a particle
// spacing, and the last two runs agree on the share within 10 % and on the crack's direction
// within 3 degrees.
void expect_dt_convergence(const nlohmann::json& doc, const double (&dts)[3]) {
  std::vector<Vec3d> path[3];
  std::vector<CrackFigures> c[3];
  for (int k = 0; k < 3; ++k) {
    nlohmann::json d = doc;
    d["time"]["max_dt"] = dts[k];
    c[k] = tear_strip(d, {9, 15}, "max_dt " + std::to_string(dts[k]), &path[k]);
  }
  const double spacing = 0.005;
  const double d1 = mean_nearest_distance(path[0], path[1]);
  const double d2 = mean_nearest_distance(path[1], path[2]);
  const double s1 = std::abs(c[1][0].fraction - c[0][0].fraction);
  const double s2 = std::abs(c[2][0].fraction - c[1][0].fraction);
  std::printf("  crack path moves %.2g, then %.2g; the share at frame 9 by %.2g, then %.2g\n",
              d1, d2, s1, s2);
  ASSERT_GT(c[0][0].fraction, 0.01);
  EXPECT_LT(s2, s1);
  ASSERT_GT(c[2].back().fraction, 0.1);
  EXPECT_LT(d2, d1);
  EXPECT_LT(d1, 0.5 * spacing);
  EXPECT_NEAR(c[1].back().fraction / c[2].back().fraction, 1, 0.1);
  EXPECT_LT(angle_between(c[1].back().angle_degrees, c[2].back().angle_degrees), 3);
}

// The strip with FLIP relaxing at 0.00078 s (flip_ratio 0.95 at the elastic step), so that
// the transfer's damping does not depend on the step. APIC (the default) and PIC damp the
// particles' velocity detail at every transfer, so a run with more steps is more damped, and
// the cracks drift as dt shrinks (frame 15, dt 3.9e-5 -> 2e-5 -> 1e-5 -> 5e-6: at l0 = dx / 2
// the path moves 0.0008, 0.0010, 0.0016; at l0 = 2 dx the crack turns from 46 to 33, 28 and
// 24.5 degrees; docs/materials.md "Resolution").
nlohmann::json relaxed_flip_strip() {
  nlohmann::json doc = with(strip(60), "explicit", 0.02);
  doc["transfer"] = "flip";
  doc["flip_relaxation_time"] = 7.8e-4;
  return doc;
}

TEST(StripTear, CrackConvergesAsDtShrinksAtTheDefaultL0) {
  // l0 = dx / 2. Measured: cracked 4.9, 4.4, 4.2 % at frame 9; at frame 15 the cracked sets
  // move by 0.0005, then 0.0002; at 52.3, 52.5, 51.0 degrees; cracked 19.1, 19.6, 20.1 % (then
  // 20.9, 21.6, 21.4, 21.3 % down to dt 6.25e-7: the share at frame 15 creeps by half a
  // percent per halving until dt is about 2.5e-6, then settles; docs/materials.md).
  expect_dt_convergence(relaxed_flip_strip(), {2e-4, 2e-5, 1e-5});
}

TEST(StripTearStudy, CrackConvergesAsDtShrinksWithL0Resolved) {
  // l0 = 0.02 = 2 dx, dt 2e-5, 1e-5, 5e-6. Measured: cracked 2.8, 3.0, 3.0 % at frame 9; at
  // frame 15 the cracked sets move by 0.0003, then 0.0002; at 33.2, 34.5, 34.5 degrees;
  // cracked 26.0, 26.6, 27.4 %.
  nlohmann::json doc = relaxed_flip_strip();
  doc["damage"]["l0"] = 0.02;
  expect_dt_convergence(doc, {2e-5, 1e-5, 5e-6});
}

TEST(StripTearStudy, CrackPathConvergesAsDxShrinksWithL0FixedInSceneUnits) {
  // l0 = 0.02 with dx 0.02, 0.01, 0.005 (l0 = 1, 2, 4 dx; 1 200 to 19 200 particles). The
  // band keeps its width in scene units (it is l0's), and the cracked sets get closer.
  // Measured at frame 15: they move by 0.021, then 0.012; cracked 28.5, 27.6, 28.2 %.
  std::vector<Vec3d> path[3];
  std::vector<CrackFigures> c[3];
  const double dxs[3] = {0.02, 0.01, 0.005};
  for (int k = 0; k < 3; ++k) {
    nlohmann::json doc = with(strip(60), "explicit", 0.02);
    doc["damage"]["l0"] = 0.02;
    doc["grid"]["dx"] = dxs[k];
    c[k] = tear_strip(doc, {15}, "dx " + std::to_string(dxs[k]), &path[k]);
  }
  const double d1 = mean_nearest_distance(path[0], path[1]);
  const double d2 = mean_nearest_distance(path[1], path[2]);
  std::printf("  crack path moves %.2g, then %.2g\n", d1, d2);
  EXPECT_LT(d2, d1);
  EXPECT_LT(d2, 0.02);  // less than l0
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(c[k].back().fraction / c[2].back().fraction, 1, 0.15) << dxs[k];
    EXPECT_LT(angle_between(c[k].back().angle_degrees, c[2].back().angle_degrees), 10) << dxs[k];
  }
}

// 3D: examples/tube_tear_3d.json (a tube with fibers at 45 degrees in the x-y plane pulled
// along its axis), sampled at random instead of on the lattice. Its walls tear along the fibers
// from frame ~26 and the tube comes apart by frame ~32; the bands stay sharp (within 4 particle
// spacings) and do not widen afterwards.
TEST(TubeTear3D, BandsFollowTheFibersAndStaySharpAfterTheTubeComesApart) {
  std::ifstream in(std::string(TEAR_SOURCE_DIR) + "/examples/tube_tear_3d.json");
  ASSERT_TRUE(in) << "examples/tube_tear_3d.json";
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["objects"][0].erase("sampling");
  const std::vector<int> frames = {32, 38};
  const std::vector<CrackFigures> c =
      tear<3>(parse_scene(doc, "tube_tear_3d.json"), frames, "tube");
  ASSERT_GT(c[0].fraction, 0.05);
  const Vec3d fiber = Vec3d(1, 1, 0).normalized();
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(std::abs(c[k].normal.dot(fiber)), std::sin(10 * kPi / 180)) << frames[k];
    EXPECT_LE(c[k].width_spacings, 4) << frames[k];
  }
  EXPECT_LE(c[1].width_spacings, c[0].width_spacings + 0.5);
}

}  // namespace
}  // namespace tear
