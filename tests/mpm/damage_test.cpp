// Explicit phase-field damage in the solver: bounds, monotonicity, materials without damage.
#include "tear/mpm/solver.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace tear {
namespace {

// Two blocks side by side, pulled apart vertically by sticky grips: the left one can be
// damaged (fibers at 45 degrees), the right one has no damage parameters.
Scene pulled_blocks() {
  const nlohmann::json doc = nlohmann::json::parse(R"({
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
  return parse_scene(doc, "pulled_blocks.json");
}

TEST(ExplicitDamage, BoundedMonotoneAndOnlyWhereEnabled) {
  MpmSolver<2> sim(pulled_blocks());
  const size_t n = sim.particles().size();
  std::vector<Real> d_prev(n, 0), h_prev(n, 0);
  int growing_steps = 0;
  for (int step = 0; step < 1500; ++step) {
    sim.step(sim.estimate_dt());
    const Particles<2>& p = sim.particles();
    bool grew = false;
    for (size_t i = 0; i < n; ++i) {
      const uint32_t id = p.id[i];
      ASSERT_GE(p.damage[i], d_prev[id]) << "damage decreased, particle " << id;
      ASSERT_LE(p.damage[i], 1);
      ASSERT_GE(p.drive[i], h_prev[id]) << "history decreased, particle " << id;
      if (p.material[i] == 1) {
        ASSERT_EQ(p.damage[i], 0);  // "plain" has no damage
      }
      grew |= p.damage[i] > d_prev[id];
      d_prev[id] = p.damage[i];
      h_prev[id] = p.drive[i];
    }
    growing_steps += grew;
  }
  // The test is not vacuous: the fibrous block did crack.
  Real max_d = 0;
  for (Real d : d_prev) max_d = std::max(max_d, d);
  EXPECT_GT(max_d, 0.9);
  EXPECT_GT(growing_steps, 50);
}

}  // namespace
}  // namespace tear
