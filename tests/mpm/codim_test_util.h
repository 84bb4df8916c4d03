// Helpers for the codimensional MPM tests (codim_test.cpp, codim_implicit_test.cpp).
#pragma once

#include "mpm_test_util.h"

namespace tear::testing {

// A cloth sheet (random triangulation) and a rope, both spinning and translating, beside a
// spinning jelly block, in free flight (no gravity, no walls): they meet and push each other.
inline constexpr const char* kMixedCodimFlight3d = R"({
  "dim": 3, "seed": 3,
  "grid": {"dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [2, 2, 2], "walls": "none"},
  "time": {"frame_dt": 0.01, "frames": 1, "cfl": 0.4, "max_dt": 1e-3},
  "materials": {
    "cloth": {"model": "surface_qr", "E": 2000, "nu": 0.3, "rho": 50, "friction": 0.4},
    "jelly": {"model": "neo_hookean", "E": 500, "nu": 0.3, "rho": 20},
    "yarn": {"model": "curve_qr", "E": 3000, "nu": 0.3, "rho": 80}
  },
  "objects": [
    {"kind": "surface", "material": "cloth", "thickness": 0.01,
     "shape": {"type": "sheet", "center": [1, 1, 1], "size": [0.5, 0.4], "resolution": [10, 8],
               "triangulation": "random",
               "transform": {"rotate": {"axis": [1, 0.3, 0], "angle_deg": 30}}},
     "velocity": [0.3, 0.1, -0.2], "angular_velocity": [1, 2, 0.5]},
    {"kind": "curves", "material": "yarn", "radius": 0.01,
     "shape": {"type": "rope", "from": [0.7, 0.8, 0.8], "to": [1.3, 1.1, 1.2], "segments": 24},
     "velocity": [-0.2, 0.3, 0.1], "angular_velocity": [0, 1.5, -1]},
    {"material": "jelly", "shape": {"type": "box", "min": [0.8, 1.05, 0.8], "max": [1.1, 1.25, 1.1]},
     "velocity": [0, -0.4, 0], "angular_velocity": [0.5, 0, 1]}
  ]
})";

// A scene's solids and codimensional bodies as particle groups, ready to step.
template <int Dim>
MpmSim<Dim> codim_sim(const Scene& s) {
  return MpmSim<Dim>(s, sample_scene_groups<Dim>(s));
}

}  // namespace tear::testing
