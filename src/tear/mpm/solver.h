// mpm/: the explicit MPM step of paper Fig. 13:
//   sort -> damage (explicit or implicit phase field, mpm/damage_step.cpp) -> P2G (APIC/MLS
//   momentum and degraded stress) -> grid update (gravity, walls, colliders) -> G2P
//   (velocity, affine matrix, position, F).
#pragma once

#include "tear/grid/sparse_grid.h"
#include "tear/materials/material.h"
#include "tear/mpm/simulation.h"
#include "tear/particles/particles.h"
#include "tear/scene/scene.h"

#include <vector>

namespace tear {

// Implicit damage solves since the counters were last reset (stats.jsonl figures).
struct DamageSolveStats {
  long solves = 0;
  long iterations = 0;      // sweeps, summed over the solves
  int iterations_max = 0;   // sweeps of one solve
  double change_max = 0;    // largest change of a particle's damage in a solve's last sweep
  long unconverged = 0;     // solves that stopped at damage.max_iterations
};

template <int Dim>
class MpmSolver {
 public:
  // Samples the scene's objects into particles.
  explicit MpmSolver(const Scene& scene);
  // Uses the given particles instead (tests, resumed runs).
  MpmSolver(const Scene& scene, Particles<Dim> particles);

  // min(max_dt, cfl dx / max|v_p|, cfl dx / wave speed, explicit damage limit)
  // (ARCHITECTURE.md "One explicit step"; docs/materials.md "Time step").
  double estimate_dt() const { return dt_limits().dt(); }
  DtLimits dt_limits() const;
  // The explicit damage update's step limit, eta / (1 + min(D, kDriveCap) + 4 dim l0^2 / dx^2)
  // over the damageable particles not yet fully cracked; with `cracking`, the limit once a
  // crack grows (D = kDriveCap). Infinity for the implicit solver and without damage.
  double damage_dt_limit(bool cracking = false) const;
  // Driving forces above this count as this in the explicit step limit (the overshoot they
  // could cause is below 1 / (1 + kDriveCap)).
  static constexpr double kDriveCap = 99;
  // Spectral radius of l0^2 L (the particles' damage Laplacian) per (2 l0 / dx)^2: 0.26-0.35
  // measured on lattice and random samplings in 2D and 3D, rounded up.
  static constexpr double kLaplacianRadius = 0.4;
  // One symplectic Euler step of size dt from time() to time() + dt.
  void step(double dt);

  // The damage update of one step alone, particles held still (tests): bins the particles,
  // then does what step() does for damage.
  void damage_step(double dt);
  const DamageSolveStats& damage_stats() const { return damage_stats_; }
  DamageSolveStats& damage_stats() { return damage_stats_; }

  const Particles<Dim>& particles() const { return p_; }
  Particles<Dim>& particles() { return p_; }
  const SparseGrid<Dim>& grid() const { return grid_; }
  const Scene& scene() const { return scene_; }
  const std::vector<MaterialParams>& materials() const { return mats_; }
  double time() const { return time_; }
  void set_time(double t) { time_ = t; }
  long steps() const { return steps_; }
  const PhaseTimes& phase_times() const { return times_; }
  // Home slots at the last reorder: part of the restartable state, because the reorder
  // decision (and so the summation order) depends on it.
  const std::vector<int>& slots_at_reorder() const { return slot_at_permute_; }
  // Replace the state by a checkpointed one (particles in their saved order).
  void restore(Particles<Dim> particles, std::vector<int> slots_at_reorder, double time,
               long steps);

  // Conserved figures and energies of the particle state (deterministic reductions).
  double total_mass() const;
  Vec3d momentum() const;
  // About the origin, including the APIC affine part m (dx^2/4) (C - C^T) (so that APIC
  // transfers conserve it).
  Vec3d angular_momentum() const;
  double kinetic_energy() const;
  double elastic_energy() const;

 private:
  void sort_particles();
  // Driving force with history (EQUATIONS.md §1), then the scene's damage solver; nothing
  // when damage.solver is none. Needs the binning of the current positions.
  void damage_update(Real dt);
  // Driving force with history (EQUATIONS.md §1) for every damageable particle; whether any
  // particle has a driving force or damage (else the damage update has nothing to do).
  bool update_driving_force();
  // Explicit phase-field damage (supplement Alg. 3-5): damage to the grid with the cubic
  // B-spline, its Laplacian back, forward Euler update.
  void damage_explicit(Real dt);
  // Implicit phase-field damage: backward Euler of the same law for the particles' damage,
  // solved by Jacobi sweeps (docs/materials.md "Damage solvers").
  void damage_implicit(Real dt);
  // g(d) of particle p: 1 for materials without damage.
  Real degradation_of(size_t p) const;
  // The (degraded) first Piola stress of particle p that P2G spreads.
  Mat<Dim> stress_for_p2g(size_t p) const;
  void p2g(Real dt);
  void grid_update(Real dt);
  void g2p(Real dt);

  Scene scene_;
  Particles<Dim> p_;
  SparseGrid<Dim> grid_;
  std::vector<MaterialParams> mats_;
  std::vector<DamageSpec> damage_;  // per material; enabled = false: never damaged
  Vec<Dim> gravity_ = Vec<Dim>::Zero();
  Vec<Dim> lo_, hi_;  // particles are kept inside [lo, hi]
  std::vector<int> slot_at_permute_;  // home slots when particles were last reordered
  double time_ = 0;
  long steps_ = 0;
  PhaseTimes times_;
  DamageSolveStats damage_stats_;
  std::vector<Real> start_damage_;  // implicit damage: d^n of the step
  // Undegraded first Piola stress of the damageable particles, from this step's driving force
  // (piola_fresh_ until P2G has used it): P2G reuses it for the particles still undamaged.
  std::vector<Mat<Dim>> piola_;
  bool piola_fresh_ = false;
};

}  // namespace tear
