// mpm/: the explicit (symplectic Euler) integrator, paper Fig. 13: one step is the phases of
// mpm/phases.h called in order. An implicit integrator will sit beside it over the same phases.
#pragma once

#include "tear/damage/damage_settings.h"
#include "tear/exec/domain.h"
#include "tear/mpm/inextensibility.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

namespace tear {

// Wall-clock seconds spent in each phase.
struct PhaseTimes {
  double sort = 0, stress = 0, damage = 0, crack_fields = 0, p2g = 0, grid = 0, inextensibility = 0,
         g2p = 0;
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
};

// What every integrator's step begins with: sort, the constitutive phase (when damage needs
// it) and the damage update, each timed.
template <int Dim>
void begin_step(const MpmSettings& settings, MpmState<Dim>* state, double dt, StepRecord* record,
                Domain& domain);

// And ends with: particles migrate between ranks, time and step counter advance.
template <int Dim>
void end_step(MpmState<Dim>* state, double dt, Domain& domain);

// One explicit step of size dt from state->time to state->time + dt. `domain` adds the halo
// exchange and migration of a multi-process run (a LocalDomain: nothing).
template <int Dim>
void explicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt, StepRecord* record,
                   Domain& domain);

// The damage update of one step alone, particles held still (tests): bins the particles and
// computes their stress, then does what a step does for damage.
template <int Dim>
void damage_only_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                      StepRecord* record, Domain& domain);

}  // namespace tear
