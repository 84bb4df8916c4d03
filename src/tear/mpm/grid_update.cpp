// The grid update phase: momenta to velocities, gravity, contact between the two velocity fields
// of a split node (crack fields), walls and colliders.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tear {

namespace {

// Momentum to velocity at one node of one field (mass m), with gravity.
template <int Dim>
void to_velocity(Real m, Vec<Dim>* v, Vec<Dim>* v_old, const Vec<Dim>& dv_gravity) {
  if (m <= 0) {
    v->setZero();
    v_old->setZero();
    return;
  }
  // MLS puts the stress impulse into the momentum already; velocity_old holds the force-free
  // momentum, so FLIP differences carry stress, gravity and boundaries.
  *v /= m;
  *v_old /= m;
  *v += dv_gravity;
}

// Frictionless contact between the two fields of a split node: where they approach along the
// crack normal, both take their common centre-of-mass normal velocity (momentum conserved).
template <int Dim>
void field_contact(SparseGrid<Dim>* grid, size_t node) {
  const Real m1 = grid->mass[node], m2 = grid->mass2[node];
  if (m1 <= 0 || m2 <= 0) return;
  // The normal points from the first field's side of the crack towards the second's.
  const Vec<Dim> n = grid->crack_normal[node].normalized();
  Vec<Dim>& v1 = grid->velocity[node];
  Vec<Dim>& v2 = grid->velocity2[node];
  const Real approach = (v1 - v2).dot(n);
  if (approach <= 0) return;
  v1 -= (m2 / (m1 + m2) * approach) * n;
  v2 += (m1 / (m1 + m2) * approach) * n;
}

}  // namespace

template <int Dim>
void grid_update(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  SparseGrid<Dim>& grid = state->grid;
  const Vec<Dim> dv_gravity = dt * settings.gravity.template head<Dim>().template cast<Real>();
  const bool split = grid.split();
  parallel_for(size_t(grid.num_blocks()), [&](size_t blk) {
    const size_t a = blk * SparseGrid<Dim>::kNodesPerBlock;
    for (size_t node = a; node < a + SparseGrid<Dim>::kNodesPerBlock; ++node) {
      to_velocity<Dim>(grid.mass[node], &grid.velocity[node], &grid.velocity_old[node], dv_gravity);
      if (!split) continue;
      to_velocity<Dim>(grid.mass2[node], &grid.velocity2[node], &grid.velocity_old2[node],
                       dv_gravity);
      field_contact(&grid, node);
    }
  });
  apply_colliders<Dim>(grid, settings.walls, settings.colliders, state->time);
}

template <int Dim>
Real smallest_particle_mass(const MpmState<Dim>& state) {
  if (state.moved_step == state.steps) return state.moved.min_mass;  // G2P's, no second pass
  Real neg_min_mass = -std::numeric_limits<Real>::infinity();
  for (const Particles<Dim>& p : state.groups)
    if (element_dimension(p.kind) == 0)  // element particles carry no mass
      neg_min_mass = std::max(neg_min_mass,
                            parallel_max<Real>(
                                p.size(), [&](size_t i) { return -p.mass[i]; },
                                -std::numeric_limits<Real>::infinity()));
  return -neg_min_mass;
}

template <int Dim>
Real grid_speed_max(const MpmState<Dim>& state, Real m_min) {
  const SparseGrid<Dim>& grid = state.grid;
  if (!(m_min > 0) || !std::isfinite(m_min)) return 0;
  // w_ip m_p <= m_i, so node i moves particle p by at most min(1, m_i / m_p) |v_i| per unit
  // time: a node at the edge of the material (little mass, often a large velocity) moves
  // nothing much.
  auto speed2 = [&](Real m, const Vec<Dim>& v) {
    if (m <= 0) return Real(0);
    const Real share = std::min(Real(1), m / m_min);
    return share * share * v.squaredNorm();
  };
  const bool split = grid.split();
  const Real v2 = parallel_max<Real>(
      grid.num_active_nodes(),
      [&](size_t node) {
        Real s = speed2(grid.mass[node], grid.velocity[node]);
        if (split) s = std::max(s, speed2(grid.mass2[node], grid.velocity2[node]));
        return s;
      },
      Real(0));
  return std::sqrt(v2);
}

template void grid_update<2>(const MpmSettings&, MpmState<2>*, Real);
template void grid_update<3>(const MpmSettings&, MpmState<3>*, Real);
template Real smallest_particle_mass<2>(const MpmState<2>&);
template Real smallest_particle_mass<3>(const MpmState<3>&);
template Real grid_speed_max<2>(const MpmState<2>&, Real);
template Real grid_speed_max<3>(const MpmState<3>&, Real);

}  // namespace tear
