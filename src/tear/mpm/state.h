// mpm/: the state of an MPM simulation, plain data: the particle groups, the sparse grid, time
// and step counter. The step's phases (mpm/phases.h) and integrators (mpm/explicit_step.h) are
// free functions over it.
#pragma once

#include "tear/grid/sparse_grid.h"
#include "tear/mpm/settings.h"
#include "tear/particles/particles.h"

#include <limits>
#include <vector>

namespace tear {

template <int Dim>
struct MpmState {
  std::vector<Particles<Dim>> groups;
  SparseGrid<Dim> grid;
  double time = 0;
  long steps = 0;
  // The implicit integrator's auto preconditioner has switched to multigrid: later steps start
  // with it (checkpointed, so that a resumed run takes the same path).
  bool implicit_multigrid = false;
  // Each group's home slots (SparseGrid::home_slot) of the positions as G2P left them, for the
  // next sort: valid while home_slots_step == steps (G2P sets it to the step it ends; any other
  // change of positions must set it to -1).
  std::vector<std::vector<int>> home_slots;
  long home_slots_step = -1;
  // What G2P saw of the particles it moved, so that the step's end and the next step need no
  // pass of their own: the largest KeptBox::speed2_or_fault (speed2_or_fault, mpm/measure.h) and
  // the smallest mass (smallest_particle_mass, mpm/phases.h). Valid while moved_step == steps,
  // as home_slots; any other change of positions, velocities or masses must set it to -1.
  struct Moved {
    Real speed2 = 0;
    Real min_mass = std::numeric_limits<Real>::infinity();
  };
  Moved moved;
  long moved_step = -1;

  bool has_codim() const {
    for (const Particles<Dim>& g : groups)
      if (g.codimensional()) return true;
    return false;
  }

  size_t num_particles() const {
    size_t n = 0;
    for (const Particles<Dim>& g : groups) n += g.size();
    return n;
  }
};

// The state at time 0 of `groups` under `settings`: the grid set up over the domain, the
// optional fields the settings need enabled (the damage history where damage is simulated),
// particles sorted into grid blocks.
template <int Dim>
MpmState<Dim> make_mpm_state(const MpmSettings& settings, std::vector<Particles<Dim>> groups);
// One group (moved in: a braced list of groups would copy them).
template <int Dim>
MpmState<Dim> make_mpm_state(const MpmSettings& settings, Particles<Dim> group);

}  // namespace tear
