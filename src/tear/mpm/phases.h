// mpm/: the phases of an MPM step (paper Fig. 13), each a free function over the state in its
// own file. An integrator is a short function that calls them in order (mpm/explicit_step.h);
// the damage phase is damage/phase_field.h's update_damage.
#pragma once

#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

namespace tear {

// Quadratic B-spline: the MPM transfer kernel (MLS-MPM, Hu et al. 2018).
constexpr int kTransferOrder = 2;

// Bin every group's particles into grid blocks and reorder a group in memory when more than a
// tenth of its particles changed home block since its last reorder (mpm/sort.cpp).
template <int Dim>
void sort_particles(MpmState<Dim>* state);

// The constitutive phase: every particle's undegraded first Piola stress P(F) and J = det F,
// once a step, for all consumers (the damage driving force, P2G) (mpm/constitutive.cpp).
template <int Dim>
void update_stress(const MpmSettings& settings, MpmState<Dim>* state);

// Particles to grid: mass, momentum with the APIC/MLS affine term and the degraded stress
// (MLS-MPM, Hu et al. 2018) (mpm/p2g.cpp).
template <int Dim>
void p2g(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// Grid velocities from momenta, gravity, then domain walls and colliders (mpm/grid_update.cpp).
template <int Dim>
void grid_update(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// Grid to particles: velocity (APIC, PIC or FLIP), affine matrix, position and
// F <- (I + dt grad v) F (mpm/g2p.cpp).
template <int Dim>
void g2p(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// The degraded first Piola stress of particle i of `p` that P2G spreads (from this step's
// undegraded stress and the particle's damage).
template <int Dim>
Mat<Dim> p2g_stress(const MpmSettings& settings, const Particles<Dim>& p, size_t i);

}  // namespace tear
