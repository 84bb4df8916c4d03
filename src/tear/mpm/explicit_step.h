// mpm/: the explicit (symplectic Euler) integrator, paper Fig. 13: one step is the phases of
// mpm/phases.h called in order. An implicit integrator will sit beside it over the same phases.
#pragma once

#include "tear/damage/damage_settings.h"
#include "tear/exec/domain.h"
#include "tear/mpm/inextensibility.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

#include <functional>

namespace tear {

// Wall-clock seconds spent in each phase.
struct PhaseTimes {
  double sort = 0, stress = 0, damage = 0, crack_fields = 0, codim = 0, p2g = 0, grid = 0,
         inextensibility = 0, g2p = 0;
};

// The implicit integrator's solves (mpm/implicit_step.h), summed over steps.
struct ImplicitSolveStats {
  long solves = 0;
  long newton_iterations = 0;  // summed over the solves
  int newton_iterations_max = 0;  // of one solve
  long cg_iterations = 0;  // summed over the Newton steps of every solve
  double residual_max = 0;  // largest final residual (Newton's measure, implicit_step.h)
  long unconverged = 0;  // solves that stopped at the Newton iteration limit
  long multigrid_solves = 0;  // Newton iterations whose linear solve used multigrid
};

// What steps leave behind besides the state: phase times and the figures of the implicit
// damage solver, the implicit integrator and the inextensibility solve (reset by whoever
// reports them).
struct StepRecord {
  PhaseTimes times;
  DamageSolveStats damage;
  ImplicitSolveStats implicit;
  InextensibilityStats inextensibility;
  long steps_redone = 0;  // steps redone with a smaller dt (integrate_step)
};

// Every integrator's step (explicit_step, implicit_step): sort; the constitutive phase (when
// damage needs it) and the damage update; `to_grid(dt)`, the integrator's own part, which
// leaves this step's grid velocities; the inextensibility projection, G2P with the plastic
// projection, migration between ranks, time and step counter. dt was sized from the velocities
// at the step's start (mpm/time_step.h); when the grid velocities would carry material further
// than kRedoCflFactor * cfl * dx (a collider that starts to push, a sudden release), the damage
// fields are put back and the step after the sort is redone with
// dt = min(dt / 2, cfl dx / max|v_i|), up to kMaxRedos times (record->steps_redone counts the
// redone steps). Returns the dt taken.
template <int Dim>
double integrate_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain,
                      const std::function<void(double dt)>& to_grid);

// One explicit step of size dt from state->time to state->time + dt, or shorter where it had to
// be redone (integrate_step); returns the dt taken. `domain` adds the halo exchange and
// migration of a multi-process run (a LocalDomain: nothing).
template <int Dim>
double explicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                     StepRecord* record, Domain& domain);

// The damage update of one step alone, particles held still (tests): bins the particles and
// computes their stress, then does what a step does for damage.
template <int Dim>
void damage_only_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain);

}  // namespace tear
