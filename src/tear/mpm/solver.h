// mpm/: the explicit MPM step of paper Fig. 13 (damage comes in a later module):
//   sort -> P2G (APIC/MLS momentum and stress) -> grid update (gravity, walls, colliders)
//   -> G2P (velocity, affine matrix, position, F).
#pragma once

#include "tear/grid/sparse_grid.h"
#include "tear/materials/material.h"
#include "tear/mpm/simulation.h"
#include "tear/particles/particles.h"
#include "tear/scene/scene.h"

#include <vector>

namespace tear {

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
  // Explicit phase-field damage (supplement Alg. 3-5, EQUATIONS.md §1): driving force with
  // history, damage to the grid with the cubic B-spline, its Laplacian back, update.
  void damage_explicit(Real dt);
  // g(d) of particle p: 1 for materials without damage.
  Real degradation_of(size_t p) const;
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
};

}  // namespace tear
