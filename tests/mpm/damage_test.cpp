// Phase-field damage in the solver, explicit and implicit: bounds, monotonicity, materials
// without damage, the analytic uniform solution, explicit/implicit agreement, eta -> 0,
// CG iteration counts, determinism.
#include "mpm_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "tear/exec/threads.h"

#include <cmath>
#include <cstdio>

namespace tear {
namespace {
using testing::MpmSim;

using testing::basic_scene;
using testing::lattice_block;

// Two blocks side by side, pulled apart vertically by sticky grips: the left one can be
// damaged (fibers at 45 degrees), the right one has no damage parameters.
Scene pulled_blocks(const std::string& solver, double eta) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "dim": 2, "grid": { "dx": 0.015625, "domain_min": [0, 0], "domain_max": [1, 1] },
    "time": { "frame_dt": 0.04, "frames": 1 },
    "damage": { "solver": "explicit" },
    "materials": {
      "fibrous": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2, "fiber_scale": [20],
                   "damage": { "sigma_c": 3, "eta": 0.1, "residual": 0.001, "alpha": -1 } },
      "plain": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2 } },
    "objects": [
      { "shape": { "type": "box", "min": [0.2, 0.3], "max": [0.45, 0.7] }, "material": "fibrous",
        "sampling": "grid", "fibers": { "type": "constant", "a1": [1, 1] } },
      { "shape": { "type": "box", "min": [0.55, 0.3], "max": [0.8, 0.7] }, "material": "plain",
        "sampling": "grid" } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.1, 0.66], "max": [0.9, 0.75] },
        "velocity": [0, 0.2] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.1, 0.25], "max": [0.9, 0.34] },
        "velocity": [0, -0.2] } ]
  })");
  doc["damage"]["solver"] = solver;
  doc["materials"]["fibrous"]["damage"]["eta"] = eta;
  return parse_scene(doc, "pulled_blocks.json");
}

struct PulledRun {
  Real max_damage = 0;
  int growing_steps = 0;
  DamageSolveStats cg;
};

// Steps the pulled blocks, asserting after every step that damage and history never
// decrease, stay in [0, 1] and finite, and that the plain block stays undamaged.
PulledRun run_pulled(const std::string& solver, double eta, int steps) {
  MpmSim<2> sim(pulled_blocks(solver, eta));
  const size_t n = sim.particles().size();
  std::vector<Real> d_prev(n, 0), h_prev(n, 0);
  PulledRun out;
  for (int step = 0; step < steps; ++step) {
    sim.step(sim.estimate_dt());
    const Particles<2>& p = sim.particles();
    bool grew = false;
    for (size_t i = 0; i < n; ++i) {
      const uint32_t id = p.id[i];
      EXPECT_TRUE(std::isfinite(p.damage[i]));
      EXPECT_GE(p.damage[i], d_prev[id]) << "damage decreased, particle " << id;
      EXPECT_LE(p.damage[i], 1);
      EXPECT_GE(p.drive[i], h_prev[id]) << "history decreased, particle " << id;
      if (p.material[i] == 1) {
        EXPECT_EQ(p.damage[i], 0);  // "plain" has no damage
      }
      grew |= p.damage[i] > d_prev[id];
      d_prev[id] = p.damage[i];
      h_prev[id] = p.drive[i];
    }
    if (::testing::Test::HasFailure()) return out;
    out.growing_steps += grew;
  }
  for (Real d : d_prev) out.max_damage = std::max(out.max_damage, d);
  out.cg = sim.damage_stats();
  return out;
}

TEST(ExplicitDamage, BoundedMonotoneAndOnlyWhereEnabled) {
  const PulledRun r = run_pulled("explicit", 0.1, 1500);
  // The test is not vacuous: the fibrous block did crack.
  EXPECT_GT(r.max_damage, 0.9);
  EXPECT_GT(r.growing_steps, 50);
}

TEST(ImplicitDamage, BoundedMonotoneAndOnlyWhereEnabled) {
  const PulledRun r = run_pulled("implicit", 0.1, 1500);
  EXPECT_GT(r.max_damage, 0.9);
  EXPECT_GT(r.growing_steps, 50);
  // The sweeps converge in very few iterations (k = dt / eta is small).
  ASSERT_GT(r.cg.solves, 100);
  EXPECT_LE(double(r.cg.iterations) / double(r.cg.solves), 3.0);
  EXPECT_EQ(r.cg.unconverged, 0);
}

TEST(ImplicitDamage, StableForVanishingMobility) {
  // eta = 1e-9 (paper Fig. 16): dt / eta ~ 1e5; backward Euler stays bounded and monotone,
  // and the sweeps still converge quickly (their error factor is about rho(l0^2 L) ~ 0.35).
  const PulledRun r = run_pulled("implicit", 1e-9, 600);
  EXPECT_GT(r.max_damage, 0.9);
  ASSERT_GT(r.cg.solves, 100);
  EXPECT_LE(double(r.cg.iterations) / double(r.cg.solves), 10.0);
  EXPECT_EQ(r.cg.unconverged, 0);
}

// 3D: a block with fibers at 45 degrees in the x-y plane, pulled apart along y.
Scene pulled_block_3d(const std::string& solver) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "dim": 3, "grid": { "dx": 0.0625, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1] },
    "time": { "frame_dt": 0.04, "frames": 1 },
    "damage": { "solver": "explicit" },
    "materials": {
      "fibrous": { "model": "qr_aniso", "E": 100, "nu": 0.25, "rho": 2, "fiber_scale": [20, 0],
                   "damage": { "sigma_c": 8, "eta": 0.1, "residual": 0.001, "alpha": [-1, 0] } } },
    "objects": [
      { "shape": { "type": "box", "min": [0.25, 0.25, 0.375], "max": [0.75, 0.75, 0.625] },
        "material": "fibrous", "sampling": "grid",
        "fibers": { "type": "constant", "a1": [1, 1, 0], "a2": [0, 0, 1] } } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0, 0.69, 0], "max": [1, 0.8, 1] },
        "velocity": [0, 0.3, 0] },
      { "type": "sticky", "shape": { "type": "box", "min": [0, 0.2, 0], "max": [1, 0.31, 1] },
        "velocity": [0, -0.3, 0] } ]
  })");
  doc["damage"]["solver"] = solver;
  return parse_scene(doc, "pulled_block_3d.json");
}

TEST(Damage3D, BothSolversCrackTheBlockBoundedAndMonotone) {
  for (const char* solver : {"explicit", "implicit"}) {
    MpmSim<3> sim(pulled_block_3d(solver));
    const size_t n = sim.particles().size();
    std::vector<Real> d_prev(n, 0);
    for (int step = 0; step < 300; ++step) {
      sim.step(sim.estimate_dt());
      const Particles<3>& p = sim.particles();
      for (size_t i = 0; i < n; ++i) {
        ASSERT_GE(p.damage[i], d_prev[p.id[i]]) << solver;
        ASSERT_LE(p.damage[i], 1) << solver;
        d_prev[p.id[i]] = p.damage[i];
      }
    }
    const Real max_d = *std::max_element(d_prev.begin(), d_prev.end());
    const double cracked =
        double(std::count_if(d_prev.begin(), d_prev.end(), [](Real d) { return d > 0.5; })) /
        double(n);
    EXPECT_GT(max_d, 0.9) << solver;
    EXPECT_GT(cracked, 0.01) << solver;
    EXPECT_LT(cracked, 0.9) << solver;  // measured: explicit 0.60, implicit 0.77
    if (std::string(solver) == "implicit") {
      const DamageSolveStats& cg = sim.damage_stats();
      ASSERT_GT(cg.solves, 0);
      EXPECT_LE(double(cg.iterations) / double(cg.solves), 3.0);
    }
  }
}

// A lattice block of damageable qr_aniso held still with F = diag(stretch(x), 1): a
// prescribed driving force.
template <class Stretch>
MpmSim<2> held_block(const std::string& solver, double eta, double l0, Stretch stretch,
                        double dx = 1.0 / 32) {
  Scene s = basic_scene(2, dx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::QrAniso, 100, 0.25,
                        2);
  s.damage.solver = solver == "explicit" ? DamageSolver::Explicit : DamageSolver::Implicit;
  s.damage.l0 = l0;
  s.damage.zeta = 1;
  s.damage.tolerance = 1e-12;
  DamageParams& d = s.materials[0].damage;
  d.enabled = true;
  d.sigma_c = 27;
  d.eta = eta;
  d.residual = 0.001;
  Particles<2> p = lattice_block<2>(s, Vec<2>(0.25, 0.25), Vec<2>(0.75, 0.75), 2,
                                    [](const Vec<2>&) { return Vec<2>::Zero(); });
  for (size_t i = 0; i < p.size(); ++i) p.F[i](0, 0) = Real(stretch(p.x[i]));
  return MpmSim<2>(s, std::move(p));
}

// Runs the damage update alone for `steps` steps up to time T; damage by particle id.
std::vector<Real> damage_after(MpmSim<2> sim, double T, int steps) {
  for (int k = 0; k < steps; ++k) sim.damage_step(T / steps);
  std::vector<Real> d(sim.particles().size());
  for (size_t i = 0; i < d.size(); ++i) d[sim.particles().id[i]] = sim.particles().damage[i];
  return d;
}

TEST(ImplicitDamage, UniformDrivingForceFollowsTheBackwardEulerOde) {
  // Uniform D: the Laplacian vanishes and eta d' = (1 - d) D - d has the solution
  // d(t) = D / (1 + D) (1 - exp(-(1 + D) t / eta)). Both schemes converge to it at first
  // order in dt (forward and backward Euler).
  const double eta = 0.05, T = 0.1;
  auto all = [](const Vec<2>&) { return 1.3; };
  MpmSim<2> probe = held_block("implicit", eta, 1.0 / 64, all);
  probe.damage_step(0);  // fills the history with the driving force
  const double D = probe.particles().drive[0];
  ASSERT_GT(D, 1);
  const double exact = D / (1 + D) * (1 - std::exp(-(1 + D) * T / eta));
  double prev_err[2] = {0, 0};
  for (int steps : {10, 100, 1000}) {
    int s = 0;
    for (const char* solver : {"explicit", "implicit"}) {
      const std::vector<Real> d = damage_after(held_block(solver, eta, 1.0 / 64, all), T, steps);
      double err = 0;
      for (Real v : d) err = std::max(err, std::abs(double(v) - exact));
      // Uniform (to round-off and the CG tolerance), and first-order convergence.
      const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
      EXPECT_LT(*hi - *lo, 1e-7) << solver << " " << steps;
      if (prev_err[s] > 0) {
        EXPECT_GT(prev_err[s] / err, 7) << solver << " " << steps;
        EXPECT_LT(prev_err[s] / err, 13) << solver << " " << steps;
      }
      prev_err[s++] = err;
    }
  }
  EXPECT_LT(prev_err[0], 2e-3);
  EXPECT_LT(prev_err[1], 2e-3);
}

TEST(ImplicitDamage, TendsToExplicitAsTheTimeStepShrinks) {
  // A smooth driving force (a Gaussian stretch across x) and l0 = 0.05 (3.2 dx): damage grows
  // in the middle and the Laplacian term shapes its profile. Both solvers integrate the same
  // semi-discrete law (forward and backward Euler), so their difference is the time error
  // alone: it halves as dt halves, whatever the grid. Backward Euler with a few large steps
  // stays close to the converged profile; forward Euler with steps beyond its limit
  // (damage_dt_limit, damage/phase_field.h) does not.
  const double eta = 0.05, T = 0.08, l0 = 0.05, dx = 1.0 / 64;
  auto bump = [](const Vec<2>& x) {
    return 1 + 0.3 * std::exp(-std::pow((x[0] - 0.5) / 0.1, 2));
  };
  auto max_diff = [](const std::vector<Real>& a, const std::vector<Real>& b) {
    double m = 0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(double(a[i] - b[i])));
    return m;
  };
  MpmSim<2> probe = held_block("explicit", eta, l0, bump, dx);
  probe.damage_step(0);  // fills the driving force history
  const double limit = probe.damage_dt_limit();
  const int fewest = int(std::ceil(T / limit));  // explicit steps within the limit
  const std::vector<Real> reference =
      damage_after(held_block("implicit", eta, l0, bump, dx), T, 2000);
  const double peak = *std::max_element(reference.begin(), reference.end());
  EXPECT_GT(peak, 0.3);
  double prev = 0;
  for (int steps : {fewest, 2 * fewest, 4 * fewest}) {
    const double diff = max_diff(damage_after(held_block("explicit", eta, l0, bump, dx), T, steps),
                                 damage_after(held_block("implicit", eta, l0, bump, dx), T, steps));
    EXPECT_LT(diff, 0.05 * peak) << steps << " steps";
    std::printf("  %d steps: max |explicit - implicit| = %.3g (peak %.3f)\n", steps, diff, peak);
    if (prev > 0) {
      EXPECT_GT(prev / diff, 1.7) << steps << " steps";
      EXPECT_LT(prev / diff, 2.3) << steps << " steps";
    }
    prev = diff;
  }
  EXPECT_LT(max_diff(damage_after(held_block("implicit", eta, l0, bump, dx), T, 4), reference),
            0.1 * peak)
      << "implicit with 4 steps";
  EXPECT_GT(max_diff(damage_after(held_block("explicit", eta, l0, bump, dx), T, 4), reference),
            0.3)
      << "explicit with 4 steps, each " << T / 4 / limit << " times its limit";
}

std::vector<Real> implicit_state(int threads) {
  const ThreadLimit limit(threads);
  MpmSim<2> sim(pulled_blocks("implicit", 0.1));
  for (int k = 0; k < 300; ++k) sim.step(sim.estimate_dt());
  std::vector<Real> out(sim.particles().damage);
  out.push_back(Real(sim.damage_stats().iterations));
  return out;
}

TEST(ImplicitDamage, SameBitsForOneAndTwoThreads) {
  EXPECT_EQ(implicit_state(1), implicit_state(2));
}

}  // namespace
}  // namespace tear
