// issue 12's strip, shared by the damage tests that tear it: [0.4, 0.6] x [0.2, 0.8],
// qr_aniso E 2000, nu 0.3, rho 1, fiber_scale 10, constant fibers at `degrees`; damage
// sigma_c 60, eta 0.02, residual 0.001, alpha -1, explicit solver; ppc 4 stratified-random,
// dx 0.01; sticky grips over both ends moving apart at 0.05 each; frames of 0.02 s, max_dt
// 2e-4.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <utility>

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

// The strip with a notch: a slit one cell tall, [0.4, 0.44] x [0.5, 0.51], cut from its left
// edge (three boxes meeting on cell faces, so no particle is sampled twice). A crack starts at
// the slit's tip, away from the grips.
inline nlohmann::json notched_strip(double degrees) {
  nlohmann::json doc = strip(degrees);
  const nlohmann::json body = doc["objects"][0];
  doc["objects"] = nlohmann::json::array();
  for (const auto& [lo, hi] :
       {std::pair<std::array<double, 2>, std::array<double, 2>>{{0.4, 0.2}, {0.44, 0.5}},
        {{0.4, 0.51}, {0.44, 0.8}},
        {{0.44, 0.2}, {0.6, 0.8}}}) {
    nlohmann::json o = body;
    o["shape"]["min"] = lo;
    o["shape"]["max"] = hi;
    doc["objects"].push_back(o);
  }
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
