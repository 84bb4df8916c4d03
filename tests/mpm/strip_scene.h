// issue 12's strip, shared by the damage tests that tear it: [0.4, 0.6] x [0.2, 0.8],
// qr_aniso E 2000, nu 0.3, rho 1, fiber_scale 10, constant fibers at `degrees`; damage
// sigma_c 60, eta 0.02, residual 0.001, alpha -1, explicit solver; ppc 4 stratified-random,
// dx 0.01; sticky grips over both ends moving apart at 0.05 each; frames of 0.02 s, max_dt
// 2e-4.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>

namespace tear::testing {

inline nlohmann::json strip(double degrees) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "dim": 2, "seed": 1,
    "grid": { "dx": 0.01, "domain_min": [0, 0], "domain_max": [1, 1], "walls": "separate" },
    "time": { "frame_dt": 0.02, "frames": 1, "max_dt": 2e-4 },
    "damage": { "solver": "explicit" },
    "materials": {
      "m": { "model": "qr_aniso", "E": 2000, "nu": 0.3, "rho": 1, "fiber_scale": [10],
             "damage": { "sigma_c": 60, "eta": 0.02, "residual": 0.001, "alpha": -1 } } },
    "objects": [
      { "shape": { "type": "box", "min": [0.4, 0.2], "max": [0.6, 0.8] }, "material": "m",
        "ppc": 4 } ],
    "boundaries": [
      { "type": "sticky", "shape": { "type": "box", "min": [0.35, 0.76], "max": [0.65, 0.85] },
        "velocity": [0, 0.05] },
      { "type": "sticky", "shape": { "type": "box", "min": [0.35, 0.15], "max": [0.65, 0.24] },
        "velocity": [0, -0.05] } ]
  })");
  const double t = degrees * 3.14159265358979323846 / 180;
  doc["objects"][0]["fibers"] = {{"type", "constant"}, {"a1", {std::cos(t), std::sin(t)}}};
  return doc;
}

// The strip without fibers in its elasticity or its damage.
inline nlohmann::json isotropic_strip() {
  nlohmann::json doc = strip(0);
  doc["materials"]["m"]["fiber_scale"] = {0};
  doc["materials"]["m"]["damage"]["alpha"] = 0;
  return doc;
}

}  // namespace tear::testing
