// damage/: the settings of anisotropic phase-field damage (EQUATIONS.md §1): the scene-wide
// solver settings, each material's parameters, and the implicit solver's figures. Plain data.
#pragma once

#include <cmath>

namespace tear {

enum class DamageSolver { None, Explicit, Implicit };

// Scene-wide phase-field settings ("damage" section of a scene).
struct DamageSettings {
  DamageSolver solver = DamageSolver::None;
  double l0 = 0;             // length scale (a scene's null resolves to 0.5 dx)
  double zeta = 1;           // slope of the driving force
  double tolerance = 1e-6;   // implicit: stop when no particle's damage changes by more
  int max_iterations = 200;  // implicit: give up (and report it) after this many sweeps
  // Crack fields (damage-gradient partitioning after Homel & Herbold 2017): a grid node
  // within reach of a particle whose damage is at least split_damage holds two velocity
  // fields, one per side of the crack, told apart by the particles' damage gradients; the
  // sides meet only in frictionless contact. Off: one velocity field per node (the paper).
  bool split_fields = false;
  double split_damage = 0.2;
};

// One material's damage parameters; enabled = false: the material never cracks.
struct DamageParams {
  bool enabled = false;
  double sigma_c = 0;        // critical stress
  double eta = 0;            // mobility
  double residual = 0;       // stiffness left at d = 1, in [0, 1)
  double alpha[2] = {0, 0};  // structural-tensor weights of a1, a2, in [-1, inf)
  // Anisotropy of the crack surface term, beta_k > -1 per fiber (a1, a2, as alpha): the
  // geometric resistance takes l0^2 M : grad grad d with M = I + sum_k beta_k w_k w_k^T, w_k
  // the deformed fiber F a_k normalised (damage/driving_force.h crack_surface_tensor). beta > 0
  // makes damage gradients along the fiber cost more, so cracks prefer to run along it.
  // 0: the paper's isotropic term.
  double surface[2] = {0, 0};

  bool anisotropic_surface() const { return surface[0] != 0 || surface[1] != 0; }
  // How much the surface term can scale the damage operator's bound (damage_dt_limit):
  // 1 + sum_k |beta_k|.
  double surface_factor() const { return 1 + std::abs(surface[0]) + std::abs(surface[1]); }
};

// Implicit damage solves since the counters were last reset (stats.jsonl figures).
struct DamageSolveStats {
  long solves = 0;
  long iterations = 0;     // sweeps, summed over the solves
  int iterations_max = 0;  // sweeps of one solve
  double change_max = 0;   // largest change of a particle's damage in a solve's last sweep
  long unconverged = 0;    // solves that stopped at damage.max_iterations
};

}  // namespace tear
