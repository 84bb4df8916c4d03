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
  long cg_iterations = 0;      // summed over the solves
  int cg_iterations_max = 0;   // of one solve
  double residual_max = 0;     // largest final relative residual
  long unconverged = 0;        // solves that hit damage.cg_max_iterations
};

template <int Dim>
class MpmSolver {
 public:
  // Samples the scene's objects into particles.
  explicit MpmSolver(const Scene& scene);
  // Uses the given particles instead (tests, resumed runs).
  MpmSolver(const Scene& scene, Particles<Dim> particles);

  // min(max_dt, cfl dx / max|v_p|, cfl dx / wave speed) (ARCHITECTURE.md "One explicit step").
  double estimate_dt() const;
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
  // Driving force with history (EQUATIONS.md §1) for every damageable particle.
  void update_driving_force();
  // Home blocks (index into grid_.home_blocks()) near particles whose damage (or, with
  // `with_drive`, driving force) is non-zero: only there can this step change the field.
  std::vector<char> active_damage_blocks(bool with_drive) const;
  // Explicit phase-field damage (supplement Alg. 3-5): damage to the grid with the cubic
  // B-spline, its Laplacian back, forward Euler update.
  void damage_explicit(Real dt);
  // Implicit phase-field damage (supplement Alg. 6-10): backward Euler system on the grid
  // (MLS weak form), Jacobi-PCG, FLIP or PIC back to the particles.
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
  // Implicit damage scratch: per-node sums, per-particle Laplacian coefficients, CG vectors.
  struct ImplicitNodeSums {  // per node, together: one cache line per node in the scatter
    Real w = 0, wd = 0;        // weight sum, weighted damage
    Real a = 0, cd = 0;        // A, the D part of c
    Real vw = 0, bd = 0;       // sum V w, diagonal of B
  };
  std::vector<ImplicitNodeSums> implicit_sums_;
  std::vector<Real> laplace_coef_, rhs_, inv_diag_, solution_;
  // Undegraded first Piola stress of the damageable particles, from this step's driving force
  // (piola_fresh_ until P2G has used it): P2G reuses it for the particles still undamaged.
  std::vector<Mat<Dim>> piola_;
  bool piola_fresh_ = false;
};

}  // namespace tear
