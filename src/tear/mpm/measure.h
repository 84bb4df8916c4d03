// mpm/: figures of an MPM state for people and tests: conserved quantities, energies and how
// much of the body is damaged. Deterministic reductions over this process's particles; a
// multi-process run sums them over ranks (Domain::sum).
#pragma once

#include "tear/exec/domain.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

namespace tear {

struct StateFigures {
  size_t particles = 0;
  double mass = 0;
  Vec3d momentum = Vec3d::Zero();
  // About the origin, including the APIC affine part m (dx^2/4) (C - C^T) (so that APIC
  // transfers conserve it).
  Vec3d angular_momentum = Vec3d::Zero();
  double kinetic_energy = 0, elastic_energy = 0;
  double max_damage = 0, mean_damage = 0;
  double damaged_fraction = 0;  // particles with d > 0.5
};

template <int Dim>
StateFigures measure_state(const MpmSettings& settings, const MpmState<Dim>& state);

// The figures of all ranks of `domain` from each rank's own (sums, the largest damage, and the
// shares of all particles).
StateFigures reduce_figures(const StateFigures& local, const Domain& domain);

// A particle that went wrong: its position or velocity is not finite (the run blew up), or it
// reached the domain's edge (particles are held one cell inside the domain; one that gets there
// left it). The one with the lowest id, so the same for any thread count. `group` < 0: none.
struct ParticleFault {
  enum class Kind { NonFinite, LeftDomain };
  int group = -1;
  size_t index = 0;
  uint32_t id = 0;
  uint16_t material = 0;
  Kind kind = Kind::NonFinite;
  Vec3d x = Vec3d::Zero(), v = Vec3d::Zero();
  explicit operator bool() const { return group >= 0; }
};

template <int Dim>
ParticleFault find_particle_fault(const MpmSettings& settings, const MpmState<Dim>& state);

// What a run checks after each step: the largest squared particle speed on this process (what
// dt_limits needs for the next step), or +infinity where some particle has a fault
// (find_particle_fault then names it) or a speed whose square overflows. G2P's figure where it
// describes the state (MpmState::moved), else one pass over the particles.
template <int Dim>
Real speed2_or_fault(const MpmSettings& settings, const MpmState<Dim>& state);

// The parts, for tests.
template <int Dim>
double total_mass(const MpmState<Dim>& state);
template <int Dim>
Vec3d total_momentum(const MpmState<Dim>& state);
template <int Dim>
Vec3d total_angular_momentum(const MpmSettings& settings, const MpmState<Dim>& state);
template <int Dim>
double kinetic_energy(const MpmState<Dim>& state);
template <int Dim>
double elastic_energy(const MpmSettings& settings, const MpmState<Dim>& state);

}  // namespace tear
