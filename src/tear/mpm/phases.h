// mpm/: the phases of an MPM step (paper Fig. 13), each a free function over the state in its
// own file. An integrator is a short function that calls them in order (mpm/explicit_step.h);
// the damage phase is damage/phase_field.h's update_damage.
#pragma once

#include "tear/exec/domain.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"

#include <limits>

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

// Whether a step runs the constitutive phase: only when damage is on, the one consumer of the
// stress before P2G. Otherwise P2G computes each particle's stress as it goes (a pass over
// the particles and the stress field's traffic fewer); the stress and J fields are then
// unused.
inline bool has_stress_phase(const MpmSettings& settings) {
  return settings.damage.solver != DamageSolver::None;
}

// Crack fields (settings.damage.split_fields): every particle's damage gradient, and at each
// grid node in reach of a particle whose damage is at least split_damage a crack normal, the
// steepest gradient among the particles in reach (mpm/crack_fields.cpp). P2G and G2P put a
// particle whose gradient opposes a node's normal into the node's second velocity field. The
// grid damage is the damage update's (damage_on_grid), halos through `domain`.
template <int Dim>
void partition_crack_fields(const MpmSettings& settings, MpmState<Dim>* state, Domain& domain);

// Calls fn(group g, home block h) for every home block of every group (grid.bins(g)), one
// colour at a time: nodes in reach of the particles of the blocks of a colour are written by
// one thread at a time, in an order that does not depend on the thread count
// (grid/sparse_grid.h).
template <int Dim, class Fn>
void scatter_home_blocks(const MpmState<Dim>& state, Fn&& fn) {
  const SparseGrid<Dim>& grid = state.grid;
  for_each_colour(
      SparseGrid<Dim>::kColours, state.groups.size(),
      [&](size_t g, int c) -> const std::vector<int>& { return grid.bins(g).colours[c]; },
      [&](size_t g, int b) { fn(g, grid.bins(g).home_blocks[size_t(b)]); });
}

// Whether a particle with damage gradient `gradient` belongs to the second velocity field of
// a node with crack normal `normal` (never where the node is not split: its normal is zero).
template <int Dim>
inline bool second_field(const Vec<Dim>& normal, const Vec<Dim>& gradient) {
  return normal.dot(gradient) < 0;
}

// Particles to grid: mass, momentum with the APIC/MLS affine term and the degraded stress
// (MLS-MPM, Hu et al. 2018) (mpm/p2g.cpp).
template <int Dim>
void p2g(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// Grid velocities from momenta, gravity, contact between crack fields, then domain walls and
// colliders (mpm/grid_update.cpp).
template <int Dim>
void grid_update(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// After the grid update, the largest speed a node can give a particle in G2P: |v_i| times
// min(1, m_i / m_min), m_min the smallest particle mass (a particle's weight at a node is at
// most m_i / m_p), over both fields of a split node. Inside the material and at colliders it is
// the node's speed; a node at the material's edge, with little mass and often a large velocity,
// counts for its share; m_min from smallest_particle_mass (mpm/grid_update.cpp).
template <int Dim>
Real grid_speed_max(const MpmState<Dim>& state, Real m_min);

// The smallest particle mass over all groups but the codimensional element particles (which
// carry none; +inf without particles), for grid_speed_max: computed once a step, not once an
// attempt.
template <int Dim>
Real smallest_particle_mass(const MpmState<Dim>& state);

// The box G2P keeps the particles in: the domain less one cell (dx) at each face, so that
// every node a particle's stencil reaches is inside the domain. A particle on its faces was
// pushed back onto it: it has left the domain (find_particle_fault, mpm/measure.h).
template <int Dim>
struct KeptBox {
  Vec<Dim> lo, hi;
  explicit KeptBox(const MpmSettings& settings) {
    for (int d = 0; d < Dim; ++d) {
      lo[d] = Real(settings.domain_min[d] + settings.dx);
      hi[d] = Real(settings.domain_max[d] - settings.dx);
    }
  }
  // 0: none; 1: x is on a face of the box (the particle was pushed back onto it); 2: x or v is
  // not finite.
  int fault_kind(const Vec<Dim>& x, const Vec<Dim>& v) const {
    if (!x.allFinite() || !v.allFinite()) return 2;
    if ((x.array() <= lo.array()).any() || (x.array() >= hi.array()).any()) return 1;
    return 0;
  }
  // What speed2_or_fault (mpm/measure.h) takes the largest of: |v|^2, or +inf for a fault (or
  // a square that overflows). As fault_kind != 0, in fewer tests (G2P runs it per particle): a
  // comparison with NaN is false, and a v that is not finite has a square that is not.
  Real speed2_or_fault(const Vec<Dim>& x, const Vec<Dim>& v) const {
    bool inside = true;
    for (int d = 0; d < Dim; ++d) inside &= (x[d] > lo[d]) & (x[d] < hi[d]);
    const Real s = v.squaredNorm();
    return inside && s <= std::numeric_limits<Real>::max() ? s
                                                          : std::numeric_limits<Real>::infinity();
  }
};

// Grid to particles: velocity (APIC, PIC or FLIP), affine matrix, position and
// F <- (I + dt grad v) F (mpm/g2p.cpp).
template <int Dim>
void g2p(const MpmSettings& settings, MpmState<Dim>* state, Real dt);

// The plastic return map of every particle whose material is plastic, on the F that G2P just
// updated (materials/plasticity.h; mpm/plasticity.cpp), and the frictional return map of every
// codimensional element (codim_return_map, materials/material.h), which records its contact
// state.
template <int Dim>
void project_plastic(const MpmSettings& settings, MpmState<Dim>* state);

// scale times the Kirchhoff stress tau = P F^T of particle i of `p` that P2G spreads, P
// degraded by the particle's damage (from this step's undegraded stress, or made here without
// a damage phase: in closed form where the model has one, materials/registry.h).
template <int Dim>
Mat<Dim> p2g_kirchhoff(const MpmSettings& settings, const Particles<Dim>& p, size_t i, Real scale);

}  // namespace tear
