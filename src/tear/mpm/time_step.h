// mpm/: the explicit time step and what limits it (ARCHITECTURE.md "One explicit step";
// docs/materials.md "Time step").
#pragma once

#include "tear/exec/domain.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

namespace tear {

// The limits on one explicit step (seconds; infinity where there is none): the scene's max_dt,
// the elastic wave speed (cfl dx / c), the particles' speed (cfl dx / max|v|) and the explicit
// damage update; `damage_cracking` is the damage limit once cracks grow (not part of dt(): a
// forecast for `tear check`).
struct DtLimits {
  double max_dt = 0, wave = 0, velocity = 0, damage = 0;
  double damage_cracking = 0;
  double dt() const;
  // "max_dt", "wave speed", "particle speed" or "explicit damage": the one that sets dt().
  const char* limiting() const;
};

// The step guard (integrate_step, mpm/explicit_step.h): a step whose grid velocities would
// carry material further than kRedoCflFactor * cfl * dx is redone with a smaller dt, at most
// kMaxRedos times (docs/long-runs.md "Steps that would move too far").
constexpr double kRedoCflFactor = 2;
constexpr int kMaxRedos = 8;

// The limits for the current state, reduced over the ranks of `domain`.
template <int Dim>
DtLimits dt_limits(const MpmSettings& settings, const MpmState<Dim>& state, const Domain& domain);

// The same, with this process's largest squared particle speed given by a caller that has it
// already (speed2_or_fault, mpm/measure.h: what G2P recorded, or one pass over the particles).
template <int Dim>
DtLimits dt_limits(const MpmSettings& settings, const MpmState<Dim>& state, const Domain& domain,
                   Real speed2);

}  // namespace tear
