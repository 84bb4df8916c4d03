// Codimensional bodies in MPM (Jiang et al. 2017; codim/elements.h): conservation in free
// flight beside a solid, a hanging rope's static stretch and its pendulum frequencies against
// the analytic chain, and the same bits on any thread count.
#include "codim_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tear/exec/threads.h"

namespace tear {
namespace {

using testing::codim_sim;
using testing::kMixedCodimFlight3d;
using testing::MpmSim;

Scene scene_of(const std::string& text) { return load_scene_text(text, "codim_test.json"); }


TEST(Codim, GroupsOfAMixedSceneHoldTheMeshes) {
  const Scene s = scene_of(kMixedCodimFlight3d);
  const std::vector<Particles<3>> groups = sample_scene_groups<3>(s);
  ASSERT_EQ(groups.size(), 5u);  // solids, curve vertices and elements, surface ones
  EXPECT_EQ(groups[0].kind, GroupKind::Volumetric);
  EXPECT_EQ(groups[1].kind, GroupKind::MeshVertices);
  EXPECT_EQ(groups[2].kind, GroupKind::CurveElements);
  EXPECT_EQ(groups[3].kind, GroupKind::MeshVertices);
  EXPECT_EQ(groups[4].kind, GroupKind::SurfaceElements);
  EXPECT_EQ(groups[1].size(), 25u);
  EXPECT_EQ(groups[2].size(), 24u);
  EXPECT_EQ(groups[3].size(), 11u * 9u);
  EXPECT_EQ(groups[4].size(), 2u * 10u * 8u);
  EXPECT_EQ(groups[2].vertex_group, 1);
  EXPECT_EQ(groups[4].vertex_group, 3);
  // The vertices hold the body's mass, rho times its volume; the elements its volume, no mass.
  for (size_t g : {1u, 3u}) {
    const Particles<3>& vx = groups[g];
    const Particles<3>& el = groups[g + 1];
    double mass = 0, volume = 0;
    for (size_t i = 0; i < vx.size(); ++i) mass += vx.mass[i];
    for (size_t e = 0; e < el.size(); ++e) {
      volume += el.vol0[e];
      EXPECT_EQ(el.mass[e], 0);
    }
    const double rho = g == 1 ? 80 : 50;
    EXPECT_NEAR(mass, rho * volume, 1e-12 * mass);
    const double expected = g == 1 ? (Vec3d(1.3, 1.1, 1.2) - Vec3d(0.7, 0.8, 0.8)).norm() *
                                         3.14159265358979323846 * 1e-4
                                   : 0.5 * 0.4 * 0.01;
    EXPECT_NEAR(volume, expected, 1e-9 * expected);
    // At rest the element's F is a rotation and its stress zero.
    for (size_t e = 0; e < el.size(); ++e) {
      const Mat<3>& F = el.F[e];
      EXPECT_LT((F.transpose() * F - Mat<3>::Identity()).norm(), 1e-12);
      EXPECT_GT(F.determinant(), 0);
    }
  }
}

template <int Dim>
void expect_free_flight_conservation(const Scene& s, int steps) {
  MpmSim<Dim> sim = codim_sim<Dim>(s);
  const double m0 = sim.total_mass();
  const Vec3d P0 = sim.momentum(), L0 = sim.angular_momentum();
  for (int i = 0; i < steps; ++i) sim.step(sim.estimate_dt());
  EXPECT_EQ(sim.total_mass(), m0);
  const double scale_p = sim.total_mass(), scale_l = L0.norm() + P0.norm();
  EXPECT_LT((sim.momentum() - P0).norm() / scale_p, 1e-12);
  EXPECT_LT((sim.angular_momentum() - L0).norm() / scale_l, 1e-12);
  // The bodies deformed: the codimensional elements carry stress.
  double energy = 0;
  for (const Particles<Dim>& p : sim.state().groups)
    if (element_dimension(p.kind) > 0)
      for (size_t e = 0; e < p.size(); ++e)
        energy += p.vol0[e] * energy_density<Dim>(sim.settings().materials[p.material[e]], p.F[e],
                                                  Mat<Dim>::Identity());
  EXPECT_GT(energy, 0);
}

TEST(Codim, FreeFlightOfClothRopeAndJellyConservesMomentumAndAngularMomentum) {
  expect_free_flight_conservation<3>(scene_of(kMixedCodimFlight3d), 150);
}

TEST(Codim, FreeFlightOfSpinningCurves2DConservesMomentumAndAngularMomentum) {
  expect_free_flight_conservation<2>(scene_of(R"({
    "dim": 2,
    "grid": {"dx": 0.02, "domain_min": [0, 0], "domain_max": [1, 1], "walls": "none"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "materials": {"yarn": {"model": "curve_qr", "E": 5000, "nu": 0.3, "rho": 100}},
    "objects": [
      {"kind": "curves", "material": "yarn", "radius": 0.004,
       "shape": {"type": "rope", "from": [0.3, 0.4], "to": [0.7, 0.55], "segments": 40},
       "velocity": [0.2, -0.1], "angular_velocity": 3},
      {"kind": "curves", "material": "yarn", "radius": 0.004,
       "shape": {"type": "rope", "from": [0.45, 0.3], "to": [0.5, 0.7], "segments": 30},
       "angular_velocity": -2}
    ]
  })"), 300);
}

// Same scene, same bits, on one thread and on all.
TEST(Codim, SameBitsOnAnyThreadCount) {
  const Scene s = scene_of(kMixedCodimFlight3d);
  std::vector<std::vector<Particles<3>>> runs;
  for (int threads : {1, 0}) {
    const ThreadLimit limit(threads);
    MpmSim<3> sim = codim_sim<3>(s);
    for (int i = 0; i < 40; ++i) sim.step(sim.estimate_dt());
    runs.push_back(sim.state().groups);
  }
  for (size_t g = 0; g < runs[0].size(); ++g) {
    const Particles<3>& a = runs[0][g];
    const Particles<3>& b = runs[1][g];
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a.x[i], b.x[i]) << "group " << g << " particle " << i;
      ASSERT_EQ(a.v[i], b.v[i]);
      ASSERT_EQ(a.F[i], b.F[i]);
    }
  }
}

// A rope hanging from a sticky block under gravity g: its strain at height y is
// rho g (y - y_end) / E (the weight below over E A). Released unstretched it rings about that
// state (APIC damps little), so the strains and the end's height are averaged over many
// periods of its first longitudinal mode (4 L / c = 0.2 s here).
TEST(Codim, HangingRopeStretchesUnderItsWeight) {
  const double E = 1e5, rho = 1000, g = 10, top = 0.9, bottom = 0.4;
  Scene s = scene_of(R"({
    "dim": 2,
    "grid": {"dx": 0.02, "domain_min": [0, 0], "domain_max": [1, 1], "walls": "none"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -10],
    "materials": {"rope": {"model": "curve_qr", "E": 1e5, "nu": 0.3, "rho": 1000}},
    "objects": [{"kind": "curves", "material": "rope", "radius": 0.003,
                 "shape": {"type": "rope", "from": [0.5, 0.96], "to": [0.5, 0.4], "segments": 56}}],
    "boundaries": [{"type": "sticky", "shape": {"type": "box", "min": [0.3, 0.9], "max": [0.7, 1.2]}}]
  })");
  MpmSim<2> sim = codim_sim<2>(s);
  const Particles<2>& el = sim.state().groups[2];
  const Particles<2>& vx = sim.state().groups[1];
  while (sim.time() < 0.5) sim.step(sim.estimate_dt());
  std::vector<double> strain(el.size(), 0.0), height(el.size(), 0.0);
  double y_end = 0, total = 0;
  while (sim.time() < 2.5) {
    const double dt = sim.step(sim.estimate_dt());
    for (size_t e = 0; e < el.size(); ++e) {
      strain[e] += dt * (el.F[e].col(0).norm() - 1);
      height[e] += dt * el.x[e][1];
    }
    y_end += dt * vx.x[vx.size() - 1][1];
    total += dt;
  }
  y_end /= total;
  const double max_strain = rho * g * (top - bottom) / E;  // 5 %
  double worst = 0;
  int checked = 0;
  for (size_t e = 0; e < el.size(); ++e) {
    const double y = height[e] / total;
    if (y > top - 0.04) continue;  // the block holds the rope through the grid, within 2 cells
    worst = std::max(worst, std::abs(strain[e] / total - rho * g * (y - y_end) / E));
    ++checked;
  }
  EXPECT_GT(checked, 40);
  EXPECT_LT(worst, 0.03 * max_strain) << "max strain " << max_strain;  // measured 1.3 %
  // The end hangs by about rho g L^2 / 2E = 12.5 mm (measured 14.1: the block holds the rope
  // from about a cell and a half inside it, so the free length is 0.53, not 0.5).
  EXPECT_GT(bottom - y_end, 0.0125);
  EXPECT_LT(bottom - y_end, 0.0125 * std::pow((top - bottom + 0.04) / (top - bottom), 2));
}

// A chain hanging from a point (a stiff rope without bending), released from rest in the shape
// of its first mode, u(s) = A J0(2.405 sqrt(s / L)) (s from the free end), swings at
// omega_1 = (2.405 / 2) sqrt(g / L) (the hanging chain, Bessel J0). The sticky ball that holds
// its top holds the grid nodes within two cells, a little of the chain with them: the period
// is short by the shorter free length, less so on a finer grid.
double hanging_chain_period(double dx) {
  const double L = 0.5, z1 = 2.404825557695773, A = 0.02, x0 = 0.6, top = 0.9;
  const int segments = int(std::lround(L / (dx / 2)));
  const std::string file = ::testing::TempDir() + "hanging_chain_" + std::to_string(segments) + ".obj";
  {
    std::FILE* f = std::fopen(file.c_str(), "w");
    for (int k = 0; k <= segments; ++k) {
      const double s = L * k / segments;  // from the free end
      std::fprintf(f, "v %.9f %.9f 0\n", x0 + A * std::cyl_bessel_j(0.0, z1 * std::sqrt(s / L)),
                   top - (L - s));
    }
    std::fprintf(f, "l");
    for (int k = 1; k <= segments + 1; ++k) std::fprintf(f, " %d", k);
    std::fprintf(f, "\n");
    std::fclose(f);
  }
  Scene s = scene_of(R"({
    "dim": 2,
    "grid": {"dx": 0.02, "domain_min": [0, 0], "domain_max": [1.2, 1], "walls": "none"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -9.81],
    "materials": {"chain": {"model": "curve_qr", "E": 2e6, "nu": 0.3, "rho": 1000}},
    "objects": [{"kind": "curves", "material": "chain", "radius": 0.003,
                 "shape": {"type": "mesh", "file": ")" + file + R"("}}],
    "boundaries": [{"type": "sticky", "shape": {"type": "sphere", "center": [0.6, 0.9], "radius": 0.04}}]
  })");
  s.dx = dx;
  s.boundaries[0].shape.radius = 2 * dx;
  MpmSim<2> sim = codim_sim<2>(s);
  const Particles<2>& vx = sim.state().groups[1];
  const size_t end = 0;  // the free end: the file's first vertex
  std::vector<double> crossings;
  double prev = vx.x[end][0] - x0, t_prev = 0;
  while (sim.time() < 2.5) {
    sim.step(sim.estimate_dt());
    const double cur = vx.x[end][0] - x0;
    if ((prev > 0) != (cur > 0))
      crossings.push_back(t_prev + (sim.time() - t_prev) * prev / (prev - cur));
    prev = cur, t_prev = sim.time();
  }
  EXPECT_GE(crossings.size(), 4u);
  if (crossings.size() < 2) return 0;
  return 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
}

TEST(Codim, HangingChainSwingsAtTheBesselFrequency) {
  const double L = 0.5, g = 9.81, z1 = 2.404825557695773;
  const double expected = 2 * 3.14159265358979323846 / (z1 / 2 * std::sqrt(g / L));
  const double coarse = hanging_chain_period(0.02), fine = hanging_chain_period(0.01);
  EXPECT_NEAR(coarse, expected, 0.03 * expected);  // measured -1.6 %
  EXPECT_NEAR(fine, expected, 0.015 * expected);
  EXPECT_LT(std::abs(fine - expected), std::abs(coarse - expected));  // converges
}

// A square sheet dropped onto a sphere drapes over it with the square's symmetries (the regular
// triangulation alternates its diagonals, so the mesh has them for an even resolution, and so
// has the grid about the sphere's centre): mirror images about x = 0.5 and the diagonal agree to
// round-off. No vertex goes deeper into the sphere than a fraction of a cell (the grid
// collides nodes, not vertices: measured 0.25 dx at dx 0.02 and at 0.01).
TEST(Codim, SheetDrapesSymmetricallyOverASphere) {
  const double dx = 0.02, radius = 0.1;
  const Vec3d centre(0.5, 0.45, 0.5);
  Scene s = scene_of(R"({
    "dim": 3,
    "grid": {"dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "separate"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -9.81, 0],
    "materials": {"cloth": {"model": "surface_qr", "E": 5e4, "nu": 0.3, "rho": 200, "friction": 0.3}},
    "objects": [{"kind": "surface", "material": "cloth", "thickness": 0.002,
                 "shape": {"type": "sheet", "center": [0.5, 0.58, 0.5], "size": [0.4, 0.4],
                           "resolution": [16, 16]}}],
    "boundaries": [{"type": "separate", "friction": 0.3,
                    "shape": {"type": "sphere", "center": [0.5, 0.45, 0.5], "radius": 0.1}}]
  })");
  MpmSim<3> sim = codim_sim<3>(s);
  const Particles<3>& vx = sim.state().groups[1];
  const int n = 17;  // vertices a side, row by row along x
  while (sim.time() < 0.3) sim.step(sim.estimate_dt());
  double deepest = 0, lowest = 1;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      const Vec<3>& x = vx.x[size_t(k * n + i)];
      const Vec<3>& mirror = vx.x[size_t(k * n + (n - 1 - i))];
      const Vec<3>& diagonal = vx.x[size_t(i * n + k)];
      ASSERT_NEAR(x[1], mirror[1], 1e-10) << i << " " << k;
      ASSERT_NEAR(x[0] - 0.5, 0.5 - mirror[0], 1e-10) << i << " " << k;
      ASSERT_NEAR(x[1], diagonal[1], 1e-10) << i << " " << k;
      ASSERT_NEAR(x[0] - 0.5, diagonal[2] - 0.5, 1e-10) << i << " " << k;
      deepest = std::max(deepest, radius - (x.cast<double>() - centre).norm());
      lowest = std::min(lowest, double(x[1]));
    }
  EXPECT_LT(deepest, 0.3 * dx);
  // It draped: the corners fell well below the sphere's top (0.55), the middle stayed on it.
  EXPECT_LT(lowest, 0.42);
  EXPECT_GT(vx.x[size_t(8 * n + 8)][1], 0.54);
}

// The drape converges under refinement: the same 40 cm sheet (quads 1.25 cells wide) dropped
// on the same ball at dx 0.04, 0.02 and 0.01; at t = 0.3 s its corners' height and distance
// from the ball's axis change less from each resolution to the next (measured: corner height
// 0.3352, 0.3478, 0.3446; distance 0.0830, 0.0573, 0.0665). The folds do not converge: with no
// bending stiffness nothing but the grid sets their size, and a mid-edge vertex hangs lower at
// every refinement (0.4776, 0.4573, 0.4162), so only the corners are asserted.
struct DrapeShape {
  double corner_y, corner_r;  // a corner's height and distance from the ball's axis
};
DrapeShape drape_at(double dx) {
  const int res = int(std::lround(0.4 / (1.25 * dx)));
  char text[2048];
  std::snprintf(text, sizeof text, R"({
    "dim": 3,
    "grid": {"dx": %.17g, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "separate"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -9.81, 0],
    "materials": {"cloth": {"model": "surface_qr", "E": 5e4, "nu": 0.3, "rho": 200, "friction": 0.3}},
    "objects": [{"kind": "surface", "material": "cloth", "thickness": 0.002,
                 "shape": {"type": "sheet", "center": [0.5, 0.58, 0.5], "size": [0.4, 0.4],
                           "resolution": [%d, %d]}}],
    "boundaries": [{"type": "separate", "friction": 0.3,
                    "shape": {"type": "sphere", "center": [0.5, 0.45, 0.5], "radius": 0.1}}]
  })", dx, res, res);
  MpmSim<3> sim = codim_sim<3>(scene_of(text));
  const Particles<3>& vx = sim.state().groups[1];
  while (sim.time() < 0.3 - 1e-9) sim.step(std::min(sim.estimate_dt(), 0.3 - sim.time()));
  const Vec<3>& corner = vx.x[0];
  return {double(corner[1]), std::hypot(double(corner[0]) - 0.5, double(corner[2]) - 0.5)};
}

TEST(Codim, SheetDrapeConvergesAsDxShrinks) {
  const DrapeShape a = drape_at(0.04), b = drape_at(0.02), c = drape_at(0.01);
  EXPECT_LT(std::abs(c.corner_y - b.corner_y), std::abs(b.corner_y - a.corner_y));
  EXPECT_LT(std::abs(c.corner_r - b.corner_r), std::abs(b.corner_r - a.corner_r));
}

// A small sheet lying on an inclined plane (a separating collider with Coulomb friction mu):
// frictionless it slides at g sin(theta); with mu = 0.5 it sticks at 15 degrees (tan 15 < mu)
// and slides at 40 degrees at about g (sin - mu cos). The grid applies friction at the nodes
// inside the plane, and a single layer's vertices also reach nodes above it, whose share of the
// weight the plane bears without friction: measured, the sheet slides at 40 degrees 12 % faster
// than the analytic rate (effective mu 0.46).
double incline_acceleration(double theta_deg, double mu, double* speed_at_end) {
  constexpr double kPi = 3.14159265358979323846;
  const double th = theta_deg * kPi / 180, dx = 0.02;
  const Vec3d n(std::sin(th), std::cos(th), 0), t(std::cos(th), -std::sin(th), 0);
  const Vec3d p(0.5, 0.3, 0.5), c = p + 0.6 * dx * n;
  char text[2048];
  std::snprintf(text, sizeof text, R"({
    "dim": 3,
    "grid": {"dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "none"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -9.81, 0],
    "materials": {"cloth": {"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 200}},
    "objects": [{"kind": "surface", "material": "cloth", "thickness": 0.002,
                 "shape": {"type": "sheet", "center": [0, 0, 0], "size": [0.16, 0.16], "resolution": [8, 8],
                           "transform": {"rotate": {"axis": [0, 0, 1], "angle_deg": %.17g},
                                         "translate": [%.17g, %.17g, %.17g]}}}],
    "boundaries": [{"type": "separate", "friction": %.17g,
                    "shape": {"type": "half_space", "point": [0.5, 0.3, 0.5], "normal": [%.17g, %.17g, 0]}}]
  })", -theta_deg, c.x(), c.y(), c.z(), mu, n.x(), n.y());
  MpmSim<3> sim = codim_sim<3>(scene_of(text));
  const Particles<3>& vx = sim.state().groups[1];
  auto speed = [&] {
    double sum = 0;
    for (size_t i = 0; i < vx.size(); ++i) sum += vx.v[i].cast<double>().dot(t);
    return sum / double(vx.size());
  };
  while (sim.time() < 0.1) sim.step(sim.estimate_dt());
  const double v0 = speed(), t0 = sim.time();
  while (sim.time() < 0.2) sim.step(sim.estimate_dt());
  *speed_at_end = speed();
  return (*speed_at_end - v0) / (sim.time() - t0);
}

TEST(Codim, SheetOnAnInclineSlidesOrSticksByItsFrictionAngle) {
  constexpr double kPi = 3.14159265358979323846, g = 9.81;
  double v = 0;
  const double free = incline_acceleration(40, 0, &v);
  EXPECT_NEAR(free, g * std::sin(40 * kPi / 180), 0.01 * g);  // measured 6.305 for 6.306
  const double slides = incline_acceleration(40, 0.5, &v);
  const double analytic = g * (std::sin(40 * kPi / 180) - 0.5 * std::cos(40 * kPi / 180));
  EXPECT_GT(slides, analytic);
  EXPECT_LT(slides, 1.15 * analytic);  // measured 2.86 for 2.55
  const double sticks = incline_acceleration(15, 0.5, &v);
  EXPECT_LT(sticks, 0);  // slowing down
  EXPECT_LT(std::abs(v), 0.01);  // next to still (it starts at rest)
}

// Cloth on cloth on an incline, the return map's friction: a small sheet lies two cells above a
// larger one whose border is pinned (gravity tilted by theta instead of the planes), so the two
// meet only through the grid and the top sheet's elements, whose shear the return map caps at
// c_F times their normal compression. Below the friction angle atan(c_F) (26.6 degrees for
// c_F = 0.5) the top sheet comes to rest; above it, it keeps sliding; more friction, less slip.
// What the grid adds (measured, dx 0.02): layers within a kernel share node velocities, so the
// slide is a steady creep of 0.1-0.3 m/s rather than the acceleration g (sin - c_F cos) of two
// rigid plates (0.17 m/s at 32 degrees; half that at dx 0.01: the coupling shrinks with dx), and
// without friction the sheet accelerates at about half of g sin theta.
// Returns the top sheet's mean slide (m) in [0.2, 0.3] s and in [0.3, 0.4] s.
std::pair<double, double> cloth_on_cloth_slide(double theta_deg, double c_f) {
  constexpr double kPi = 3.14159265358979323846, g = 9.81, dx = 0.02;
  const double th = theta_deg * kPi / 180, y1 = 0.3 + 0.6 * dx, y2 = y1 + 2 * dx;
  // Sticky strips over the bottom sheet's border (x, z in [0.38, 0.62]), down into the plane.
  std::string pins;
  const double lo = 0.38, hi = 0.62, w = 0.5 * dx;
  const double strips[4][4] = {{lo - w, lo + w, lo - w, hi + w}, {hi - w, hi + w, lo - w, hi + w},
                               {lo - w, hi + w, lo - w, lo + w}, {lo - w, hi + w, hi - w, hi + w}};
  for (const auto& b : strips) {
    char pin[256];
    std::snprintf(pin, sizeof pin,
                  R"(, {"type": "sticky", "shape": {"type": "box", "min": [%.17g, 0.28, %.17g],
                   "max": [%.17g, %.17g, %.17g]}})",
                  b[0], b[2], b[1], y1 + 0.6 * dx, b[3]);
    pins += pin;
  }
  char text[4096];
  std::snprintf(text, sizeof text, R"({
    "dim": 3,
    "grid": {"dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "none"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [%.17g, %.17g, 0],
    "materials": {"cloth": {"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 200, "friction": %.17g}},
    "objects": [
      {"kind": "surface", "material": "cloth", "thickness": 0.002,
       "shape": {"type": "sheet", "center": [0.5, %.17g, 0.5], "size": [0.24, 0.24], "resolution": [16, 16]}},
      {"kind": "surface", "material": "cloth", "thickness": 0.002,
       "shape": {"type": "sheet", "center": [0.5, %.17g, 0.5], "size": [0.12, 0.12], "resolution": [8, 8]}}],
    "boundaries": [{"type": "separate", "shape": {"type": "half_space", "point": [0.5, 0.3, 0.5], "normal": [0, 1, 0]}}%s]
  })", g * std::sin(th), -g * std::cos(th), c_f, y1, y2, pins.c_str());
  MpmSim<3> sim = codim_sim<3>(scene_of(text));
  const Particles<3>& vx = sim.state().groups[1];  // both sheets: the bottom's 17 x 17 first
  const size_t bottom = 17 * 17;
  EXPECT_EQ(vx.size(), bottom + 9 * 9);
  auto mean_x = [&] {
    double sum = 0;
    for (size_t i = bottom; i < vx.size(); ++i) sum += vx.x[i][0];
    return sum / double(vx.size() - bottom);
  };
  double at[3];
  for (int k = 0; k < 3; ++k) {
    while (sim.time() < 0.2 + 0.1 * k - 1e-9) sim.step(sim.estimate_dt());
    at[k] = mean_x();
  }
  // The bottom sheet stays where its pins hold it, stretched a little downhill by its own weight
  // (3 mm, under a sixth of a cell, at 40 degrees).
  double bottom_x = 0;
  for (size_t i = 0; i < bottom; ++i) bottom_x += vx.x[i][0] - 0.5;
  EXPECT_LT(std::abs(bottom_x / double(bottom)), 0.004) << theta_deg << " deg";
  return {at[1] - at[0], at[2] - at[1]};
}

TEST(Codim, ClothOnClothSticksBelowItsFrictionAngleAndSlidesAbove) {
  // Below atan(0.5): coming to rest (measured 0.9 and 0.3 mm at 15 degrees, 3.5 and 1.7 mm at
  // 22 degrees).
  for (const double theta : {15.0, 22.0}) {
    const auto [first, last] = cloth_on_cloth_slide(theta, 0.5);
    EXPECT_LT(last, 0.002) << theta;
    EXPECT_LT(last, 0.6 * first) << theta;
  }
  // Above: a steady slide (measured 18.3 and 17.5 mm at 32 degrees).
  const auto [first32, last32] = cloth_on_cloth_slide(32, 0.5);
  EXPECT_GT(last32, 0.01);
  EXPECT_GT(last32, 0.8 * first32);
  // At 40 degrees, less friction slides further: 137 mm (accelerating), 29 mm, 11 mm in the
  // last 0.1 s for c_F = 0, 0.5, 1 (atan 1 = 45 degrees: at rest soon after).
  const double free = cloth_on_cloth_slide(40, 0).second, half = cloth_on_cloth_slide(40, 0.5).second,
               one = cloth_on_cloth_slide(40, 1).second;
  EXPECT_GT(free, 2 * half);
  EXPECT_GT(half, 1.5 * one);
  EXPECT_LT(one, 0.015);
}

// Three sheets a cell apart fall on a frictional floor and a ball rolls over them, pressing
// them down and dragging them sideways: the layers meet only through the grid, yet none passes
// through another: at every point of the square the three keep their order. (Layers within
// one kernel width share grid velocities, so the stack moves much as one thick sheet.)
TEST(Codim, StackedSheetsPushedByABallKeepTheirOrder) {
  std::string objects;
  for (int k = 0; k < 3; ++k) {
    char o[512];
    std::snprintf(o, sizeof o, R"(%s{"kind": "surface", "material": "cloth", "thickness": 0.002,
      "shape": {"type": "sheet", "center": [0.5, %.17g, 0.5], "size": [0.4, 0.4], "resolution": [20, 20]}})",
                  k ? ", " : "", 0.2 + 0.02 * k);
    objects += o;
  }
  Scene s = scene_of(R"({
    "dim": 3,
    "grid": {"dx": 0.02, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "separate"},
    "time": {"frame_dt": 0.01, "frames": 1, "max_dt": 1e-3},
    "gravity": [0, -9.81, 0],
    "materials": {"cloth": {"model": "surface_qr", "E": 2e4, "nu": 0.3, "rho": 200, "friction": 0.3}},
    "objects": [)" + objects + R"(],
    "boundaries": [
      {"type": "separate", "friction": 0.5,
       "shape": {"type": "half_space", "point": [0, 0.15, 0], "normal": [0, 1, 0]}},
      {"type": "slip", "shape": {"type": "sphere", "center": [0.32, 0.33, 0.5], "radius": 0.08},
       "velocity": [0.5, -0.2, 0], "start": 0, "end": 0.3}]
  })");
  MpmSim<3> sim = codim_sim<3>(s);
  const Particles<3>& vx = sim.state().groups[1];
  const size_t per_sheet = 21 * 21;
  ASSERT_EQ(vx.size(), 3 * per_sheet);
  double deepest_press = 0;
  while (sim.time() < 0.3) {
    sim.step(sim.estimate_dt());
    for (size_t i = 0; i < per_sheet; ++i) {
      const double y0 = vx.x[i][1], y1 = vx.x[per_sheet + i][1], y2 = vx.x[2 * per_sheet + i][1];
      ASSERT_LT(y0, y1) << "vertex " << i << " at t " << sim.time();
      ASSERT_LT(y1, y2) << "vertex " << i << " at t " << sim.time();
      deepest_press = std::max(deepest_press, 0.24 - y2);
    }
  }
  EXPECT_GT(deepest_press, 0.02);  // the ball did press the stack down (and the floor held it)
}

}  // namespace
}  // namespace tear
