// The grid update phase: momenta to velocities, gravity, walls and colliders.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
void grid_update(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  SparseGrid<Dim>& grid = state->grid;
  const Vec<Dim> gravity = settings.gravity.template head<Dim>().template cast<Real>();
  parallel_for(size_t(grid.num_blocks()), [&](size_t blk) {
    const size_t a = blk * SparseGrid<Dim>::kNodesPerBlock;
    for (size_t node = a; node < a + SparseGrid<Dim>::kNodesPerBlock; ++node) {
      const Real m = grid.mass[node];
      if (m <= 0) {
        grid.velocity[node].setZero();
        grid.velocity_old[node].setZero();
        continue;
      }
      // MLS puts the stress impulse into the momentum already; velocity_old holds the
      // force-free momentum, so FLIP differences carry stress, gravity and boundaries.
      grid.velocity[node] /= m;
      grid.velocity_old[node] /= m;
      grid.velocity[node] += dt * gravity;
    }
  });
  apply_colliders<Dim>(grid, settings.walls, settings.colliders, state->time);
}

template void grid_update<2>(const MpmSettings&, MpmState<2>*, Real);
template void grid_update<3>(const MpmSettings&, MpmState<3>*, Real);

}  // namespace tear
