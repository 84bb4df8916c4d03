// Bending of codimensional bodies (codim/bending.h): the hinge energies' gradients and Hessians
// against finite differences, invariance under rigid motions, the discrete energies against the
// continuum's on bent shapes (a rope round a circle, a sheet round a cylinder, converging as the
// mesh refines), and cantilevers under their weight against Euler-Bernoulli's deflection, under
// the implicit integrator (2D and 3D rods, a plate strip) and explicitly at the step the bending
// limit gives.
#include "codim_test_util.h"

#include "tear/codim/bending.h"
#include "tear/codim/elements.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace tear {
namespace {

using testing::codim_sim;
using testing::MpmSim;

constexpr double kPi = 3.14159265358979323846;

Scene scene_of(const std::string& text) { return load_scene_text(text, "codim_bending_test.json"); }

// A scene with one codimensional object `object` (JSON) of material "m" `material` (JSON).
template <int Dim>
MpmSim<Dim> one_object(const std::string& material, const std::string& object,
                       const std::string& extra = "") {
  const std::string box = Dim == 3 ? R"("domain_min": [0, 0, 0], "domain_max": [2, 2, 2])"
                                   : R"("domain_min": [0, 0], "domain_max": [2, 2])";
  return codim_sim<Dim>(scene_of("{\"dim\": " + std::to_string(Dim) +
                                 ", \"grid\": {\"dx\": 0.05, " + box + ", \"walls\": \"none\"}," +
                                 "\"time\": {\"frame_dt\": 0.01, \"frames\": 1}," + extra +
                                 "\"materials\": {\"m\": " + material + "}, \"objects\": [" + object + "]}"));
}

template <int Dim>
std::pair<Particles<Dim>*, Particles<Dim>*> element_and_vertex_groups(MpmSim<Dim>& sim) {
  for (Particles<Dim>& g : sim.state().groups)
    if (element_dimension(g.kind) > 0) {
      Particles<Dim>* vx = &sim.state().groups[size_t(g.vertex_group)];
      build_hinges(sim.settings().materials, *vx, &g);
      return {&g, vx};
    }
  return {nullptr, nullptr};
}

// Hinge h's Hessian on its corners' stacked coordinates, column by column through
// hinge_hessian_product (curves: with their matrix, projected when `project`).
template <int Dim>
Eigen::MatrixXd hinge_matrix(const Particles<Dim>& el, size_t h, const std::vector<Vec<Dim>>& x,
                             bool project) {
  const uint32_t n = el.hinges.corners(h);
  const CurveHingeHessian<Dim> curve = element_dimension(el.kind) == 1
                                           ? curve_hinge_hessian(el, h, x.data(), project)
                                           : CurveHingeHessian<Dim>::Zero();
  Eigen::MatrixXd M(n * Dim, n * Dim);
  std::vector<Vec<Dim>> u(x.size(), Vec<Dim>::Zero()), y(n);
  for (uint32_t c = 0; c < n; ++c)
    for (int a = 0; a < Dim; ++a) {
      const uint32_t v = el.hinges.corner[el.hinges.begin[h] + c];
      u[v][a] = 1;
      hinge_hessian_product(el, h, &curve, u.data(), y.data());
      u[v][a] = 0;
      for (uint32_t d = 0; d < n; ++d)
        for (int b = 0; b < Dim; ++b) M(d * Dim + b, c * Dim + a) = double(y[d][b]);
      const Vec<Dim> diag = hinge_hessian_diagonal(el, h, &curve, c);
      EXPECT_EQ(diag[a], y[c][a]);
    }
  return M;
}

// Every hinge's gradient against central differences of its energy, and its Hessian (unprojected)
// against differences of its gradient, at vertex positions moved at random by `jitter`; the
// projected Hessian positive semi-definite.
template <int Dim>
void expect_hinges_match_differences(MpmSim<Dim>& sim, double jitter, double hessian_tol) {
  auto [el, vx] = element_and_vertex_groups(sim);
  ASSERT_NE(el, nullptr);
  ASSERT_GT(el->hinges.size(), 5u);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  std::vector<Vec<Dim>> x = vx->x;
  for (Vec<Dim>& p : x)
    for (int a = 0; a < Dim; ++a) p[a] += Real(u(rng));
  const double h = 1e-6;
  double worst_g = 0, worst_h = 0;
  for (size_t k = 0; k < el->hinges.size(); ++k) {
    const uint32_t n = el->hinges.corners(k);
    std::vector<Vec<Dim>> g(n), gp(n), gm(n);
    hinge_gradient(*el, k, x.data(), g.data());
    const Eigen::MatrixXd H = hinge_matrix(*el, k, x, false);
    double gscale = 0;
    for (const Vec<Dim>& gc : g) gscale = std::max(gscale, double(gc.norm()));
    const double hscale = H.norm();
    for (uint32_t s = 0; s < n; ++s)
      for (int a = 0; a < Dim; ++a) {
        const uint32_t v = el->hinges.corner[el->hinges.begin[k] + s];
        std::vector<Vec<Dim>> xp = x, xm = x;
        xp[v][a] += Real(h), xm[v][a] -= Real(h);
        const double fd = (double(hinge_energy(*el, k, xp.data())) - double(hinge_energy(*el, k, xm.data()))) / (2 * h);
        worst_g = std::max(worst_g, std::abs(fd - double(g[s][a])) / gscale);
        hinge_gradient(*el, k, xp.data(), gp.data());
        hinge_gradient(*el, k, xm.data(), gm.data());
        for (uint32_t t = 0; t < n; ++t)
          for (int b = 0; b < Dim; ++b) {
            const double fdh = (double(gp[t][b]) - double(gm[t][b])) / (2 * h);
            worst_h = std::max(worst_h, std::abs(fdh - H(t * Dim + b, s * Dim + a)) / hscale);
          }
      }
    const Eigen::MatrixXd P = hinge_matrix(*el, k, x, true);
    EXPECT_LT((P - P.transpose()).norm(), 1e-12 * hscale);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * hscale);
  }
  EXPECT_LT(worst_g, 1e-6);
  EXPECT_LT(worst_h, hessian_tol);
}

TEST(CodimBending, CurveHingesMatchDifferencesIn2DAnd3D) {
  const std::string yarn = R"({"model": "curve_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 1e6})";
  MpmSim<2> s2 = one_object<2>(yarn, R"({"kind": "curves", "material": "m", "radius": 0.01,
      "shape": {"type": "rope", "from": [0.5, 1], "to": [1.5, 1.2], "segments": 20}})");
  expect_hinges_match_differences(s2, 0.02, 1e-5);
  MpmSim<3> s3 = one_object<3>(yarn, R"({"kind": "curves", "material": "m", "radius": 0.01,
      "shape": {"type": "strands", "center": [1, 1, 1], "radius": 0.2, "count": 3, "length": 0.4,
                "segments": 10}})");
  expect_hinges_match_differences(s3, 0.02, 1e-5);
}

TEST(CodimBending, SurfaceHingesMatchDifferencesOnARandomTriangulation) {
  MpmSim<3> sim = one_object<3>(
      R"({"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 1e6})",
      R"({"kind": "surface", "material": "m", "thickness": 0.01,
          "shape": {"type": "sheet", "center": [1, 1, 1], "size": [0.5, 0.4], "resolution": [6, 5],
                    "triangulation": "random"}})");
  expect_hinges_match_differences(sim, 0.03, 1e-7);  // constant: differences exact to round-off
}

// Energies of every hinge at positions x.
template <int Dim>
double bending_energy(const Particles<Dim>& el, const std::vector<Vec<Dim>>& x) {
  double e = 0;
  for (size_t h = 0; h < el.hinges.size(); ++h) e += double(hinge_energy(el, h, x.data()));
  return e;
}

// A straight rope and a flat sheet carry no bending energy or force in any rigid motion; a bent
// one's energy does not change under rigid motions.
TEST(CodimBending, RigidMotionsChangeNoEnergy) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const Vec<3> shift(0.1, -0.2, 0.05);
  auto moved = [&](const std::vector<Vec<3>>& x) {
    std::vector<Vec<3>> y = x;
    for (Vec<3>& p : y) p = (R.cast<Real>() * (p - Vec<3>(1, 1, 1)) + Vec<3>(1, 1, 1) + shift);
    return y;
  };
  for (const char* object :
       {R"({"kind": "surface", "material": "s", "thickness": 0.01,
            "shape": {"type": "sheet", "center": [1, 1, 1], "size": [0.5, 0.4], "resolution": [8, 6],
                      "triangulation": "random"}})",
        R"({"kind": "curves", "material": "c", "radius": 0.01,
            "shape": {"type": "rope", "from": [0.6, 1, 1], "to": [1.4, 1.1, 0.9], "segments": 16}})"}) {
    MpmSim<3> sim = codim_sim<3>(scene_of(std::string(R"({"dim": 3,
      "grid": {"dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [2, 2, 2], "walls": "none"},
      "time": {"frame_dt": 0.01, "frames": 1},
      "materials": {"s": {"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 1e6},
                    "c": {"model": "curve_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 1e6}},
      "objects": [)") + object + "]}"));
    auto [el, vx] = element_and_vertex_groups(sim);
    ASSERT_GT(el->hinges.size(), 10u);
    double scale = 0;  // stiffness / length^2: a force's scale
    for (size_t h = 0; h < el->hinges.size(); ++h) scale = std::max(scale, double(el->hinges.stiffness[h]));
    const std::vector<Vec<3>> flat = moved(vx->x);
    EXPECT_LT(bending_energy(*el, flat), 1e-12 * scale);
    for (size_t h = 0; h < el->hinges.size(); ++h) {
      std::vector<Vec<3>> g(el->hinges.corners(h));
      hinge_gradient(*el, h, flat.data(), g.data());
      for (const Vec<3>& f : g) EXPECT_LT(f.norm(), 1e-9 * scale);
    }
    std::vector<Vec<3>> bent = vx->x;
    for (Vec<3>& p : bent) p.y() += Real(0.3 * (p.x() - 1) * (p.x() - 1) + 0.2 * (p.z() - 1) * (p.x() - 1));
    const double e = bending_energy(*el, bent);
    EXPECT_GT(e, 0);
    EXPECT_NEAR(bending_energy(*el, moved(bent)), e, 1e-9 * e);
  }
}

// A rope of n segments of length l wound round a circle of radius R: sum over its hinges of
// B / l (1 - cos(l / R)), to (B / 2) kappa^2 (n - 1) l for small l / R.
TEST(CodimBending, RopeRoundACircleHasTheEulerBernoulliEnergy) {
  const double E_b = 2e6, r = 0.01, R = 0.3, I = kPi * r * r * r * r / 4, B = E_b * I;
  for (int n : {10, 40}) {
    const double length = 0.8, l = length / n;
    char obj[256];
    std::snprintf(obj, sizeof obj, R"({"kind": "curves", "material": "m", "radius": %g,
        "shape": {"type": "rope", "from": [0.6, 1, 1], "to": [1.4, 1, 1], "segments": %d}})", r, n);
    MpmSim<3> sim = one_object<3>(
        R"({"model": "curve_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 2e6})", obj);
    auto [el, vx] = element_and_vertex_groups(sim);
    ASSERT_EQ(el->hinges.size(), size_t(n - 1));
    std::vector<Vec<3>> x = vx->x;
    for (Vec<3>& p : x) {
      const double s = double(p.x()) - 0.6, a = s / R;
      p = Vec<3>(Real(0.6 + R * std::sin(a)), Real(1 + R * (1 - std::cos(a))), 1);
    }
    const double exact = (n - 1) * B / l * (1 - std::cos(l / R));
    EXPECT_NEAR(bending_energy(*el, x), exact, 1e-9 * exact);
    const double continuum = B / (2 * R * R) * (n - 1) * l;
    EXPECT_NEAR(exact, continuum, 0.01 * continuum);
  }
}

// A sheet of rest size a x b rolled onto a cylinder of radius R (lengths kept): the continuum
// energy is (D / 2) kappa^2 a b with D = E_b t^3 / (12 (1 - nu^2)). The border vertices carry no
// hinge, so the discrete energy lacks a strip O(1 / resolution) wide: against the continuum
// over the hinges' own areas (A_i = D / stiffness) it agrees to a few per cent, and the whole
// approaches the continuum from below as the mesh refines, on regular and random triangulations.
TEST(CodimBending, SheetRolledOntoACylinderConvergesToThePlateEnergy) {
  const double E_b = 1e6, nu = 0.3, t = 0.01, R = 0.4, a = 0.6, b = 0.5;
  const double D = E_b * t * t * t / (12 * (1 - nu * nu)), density = D / (2 * R * R);
  for (const char* triangulation : {"regular", "random"}) {
    double last_gap = 1;
    for (int n : {8, 16, 32}) {
      char obj[320];
      std::snprintf(obj, sizeof obj, R"({"kind": "surface", "material": "m", "thickness": %g,
          "shape": {"type": "sheet", "center": [1, 1, 1], "size": [%g, %g], "resolution": [%d, %d],
                    "triangulation": "%s"}})", t, a, b, n, n, triangulation);
      MpmSim<3> sim = one_object<3>(
          R"({"model": "surface_qr", "E": 1e4, "nu": 0.3, "rho": 100, "bending_modulus": 1e6})", obj);
      auto [el, vx] = element_and_vertex_groups(sim);
      std::vector<Vec<3>> x = vx->x;
      for (Vec<3>& p : x) {  // rolled about the z axis through (1, 1 + R)
        const double s = double(p.x()) - 1, ang = s / R;
        p.x() = Real(1 + R * std::sin(ang));
        p.y() = Real(1 + R * (1 - std::cos(ang)));
      }
      double interior = 0;
      for (size_t h = 0; h < el->hinges.size(); ++h) interior += D / double(el->hinges.stiffness[h]);
      const double e = bending_energy(*el, x), whole = e / (density * a * b), own = e / (density * interior);
      std::printf("[ measure  ] %s sheet %dx%d: bending energy / continuum %.4f (over the hinges' area %.4f)\n",
                  triangulation, n, n, whole, own);
      EXPECT_NEAR(own, 1, n == 8 ? 0.06 : 0.03) << triangulation << " n " << n;
      EXPECT_LT(whole, 1) << triangulation << " n " << n;
      EXPECT_LT(1 - whole, 0.6 * last_gap) << triangulation << " n " << n;
      last_gap = 1 - whole;
    }
  }
}

// A rod held at one end by a sticky box sags under its weight. Past any point a of it, the part
// beyond is a cantilever under the load beyond a alone, so the tip's deflection from the tangent
// at a is q l^4 / (8 B), l the rest length from a to the tip, q = rho A g and B = E_b I: the
// comparison does not depend on where the box's grip ends. Under the implicit integrator at ten
// times the explicit step, which also damps the swing out. 2D: a strip of unit depth, A = 2 r,
// I = (2 r)^3 / 12; 3D: A = pi r^2, I = pi r^4 / 4.
template <int Dim>
double cantilever_error(double dx, int segments_per_dx, double max_dt, double until, bool implicit,
                        double* last_dt = nullptr) {
  const double rho = 1000, g = 10, r = Dim == 2 ? 0.005 : 0.01, x0 = 0.1, x1 = 0.8, a = 0.3;
  const double A = Dim == 2 ? 2 * r : kPi * r * r, I = Dim == 2 ? 8 * r * r * r / 12 : kPi * r * r * r * r / 4;
  const double q = rho * A * g, l = x1 - a, deflection = 0.02;  // the sag the stiffness below gives
  const double B = q * l * l * l * l / (8 * deflection), E_b = B / I;
  const int segments = int(std::lround((x1 - x0) / dx)) * segments_per_dx;
  const char* z = Dim == 3 ? ", 0.5" : "";
  char text[2048];
  std::snprintf(text, sizeof text, R"({
    "dim": %d,
    "grid": {"dx": %g, "domain_min": [0, 0%s], "domain_max": [1, 1%s], "walls": "none"},
    "time": {"frame_dt": 1, "frames": 1, "max_dt": %g},
    "integrator": "%s",
    "gravity": [0, -10%s],
    "materials": {"rod": {"model": "curve_qr", "E": 1e6, "nu": 0.3, "rho": 1000, "bending_modulus": %.17g}},
    "objects": [{"kind": "curves", "material": "rod", "radius": %g,
                 "shape": {"type": "rope", "from": [%g, 0.7%s], "to": [%g, 0.7%s], "segments": %d}}],
    "boundaries": [{"type": "sticky", "shape": {"type": "box", "min": [-0.1, 0.6%s], "max": [0.2, 0.8%s]}}]
  })", Dim, dx, Dim == 3 ? ", 0" : "", Dim == 3 ? ", 1" : "", max_dt, implicit ? "implicit" : "explicit",
                Dim == 3 ? ", 0" : "", E_b, r, x0, z, x1, z, segments, Dim == 3 ? ", 0.4" : "",
                Dim == 3 ? ", 0.6" : "");
  MpmSim<Dim> sim = codim_sim<Dim>(scene_of(text));
  const Particles<Dim>& vx = sim.state().groups[1];
  EXPECT_EQ(vx.kind, GroupKind::MeshVertices);
  int steps = 0;
  const size_t ia = size_t(std::lround((a - x0) / (x1 - x0) * segments)), tip = size_t(segments);
  auto sag_now = [&] {
    const double slope = (vx.x[ia + 1][1] - vx.x[ia - 1][1]) / (vx.x[ia + 1][0] - vx.x[ia - 1][0]);
    return vx.x[ia][1] + slope * (vx.x[tip][0] - vx.x[ia][0]) - vx.x[tip][1];
  };
  while (sim.time() < until) sim.step(sim.estimate_dt()), ++steps;
  if (last_dt) *last_dt = sim.estimate_dt();
  const auto& st = sim.implicit_stats();
  std::printf("[ measure  ] %d steps, Newton %ld (max %d), CG %ld, unconverged %ld\n", steps,
              st.newton_iterations, st.newton_iterations_max, st.cg_iterations, st.unconverged);
  // The vertex at rest x = a, its neighbours' slope, the tip.
  const double sag = sag_now();
  double fastest = 0;
  for (size_t v = 0; v < vx.size(); ++v) fastest = std::max(fastest, double(vx.v[v].norm()));
  if (implicit) {
    EXPECT_LT(fastest, 0.02 * deflection / 0.33) << "Dim " << Dim << " not at rest";  // period 0.33 s
  }
  std::printf("[ measure  ] %dD cantilever dx %g, %d segments: sag %.5f, Euler-Bernoulli %.5f (%+.2f %%)\n",
              Dim, dx, segments, sag, deflection, 100 * (sag / deflection - 1));
  return sag / deflection - 1;
}

// Settled at 0.04 s steps (forty times the explicit limit) on a coarse grid, 12 segments from
// a to the tip: +4.8 % in 2D and 3D alike (the same discrete rod); CodimBendingStudy shows it
// converging.
TEST(CodimBending, CantileverRodSagsByEulerBernoulliImplicit) {
  const double e2 = cantilever_error<2>(0.04, 1, 0.04, 1.6, true);
  EXPECT_LT(std::abs(e2), 0.06);
  EXPECT_NEAR(cantilever_error<3>(0.04, 1, 0.04, 1.6, true), e2, 1e-3);
}

// The explicit step with bending: the step limit follows the bending modes (far below the
// stretch waves' here), and the rod falls into its sag without blowing up.
TEST(CodimBending, ExplicitStepIsLimitedByBendingAndStable) {
  double dt = 0;
  const double sag = cantilever_error<2>(0.04, 1, 1, 0.05, false, &dt);
  // cfl dx / c with c = omega dx / 2, omega = pi^2 sqrt(B / (rho A)) / dx^2 and B / (rho A) =
  // g l^4 / (8 sag); the stretch waves' limit, cfl dx / sqrt(E / rho), is 7.7 times longer.
  const double omega = kPi * kPi * std::sqrt(10 * std::pow(0.5, 4) / (8 * 0.02)) / (0.04 * 0.04);
  EXPECT_NEAR(dt, 0.4 * 0.04 / (omega * 0.04 / 2), 1e-3 * dt);
  EXPECT_GT(sag, -1.0);  // it sagged, past the static sag's start
  EXPECT_LT(sag, 1.5);   // from rest, at most twice the static sag
}

// ctest -L study: the cantilever under refinement, dx 0.04 -> 0.02 (12 -> 25 segments past a):
// +4.8 % -> -0.2 % (45 s on 2 threads).
TEST(CodimBendingStudy, CantileverConvergesAsDxShrinks) {
  const double coarse = cantilever_error<2>(0.04, 1, 0.04, 1.6, true);
  const double fine = cantilever_error<2>(0.02, 1, 0.04, 1.6, true);
  EXPECT_LT(std::abs(fine), 0.01);
  EXPECT_LT(std::abs(fine), 0.5 * std::abs(coarse));
}

}  // namespace
}  // namespace tear
