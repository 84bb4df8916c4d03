// The sort phase: particles binned by grid block every step, reordered in memory now and then.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

namespace {
// Reorder a group in memory when this fraction changed home block since its last reorder.
constexpr double kReorderFraction = 0.1;
}  // namespace

template <int Dim>
void sort_particles(MpmState<Dim>* state) {
  std::vector<const std::vector<Vec<Dim>>*> positions;
  for (const Particles<Dim>& g : state->groups) positions.push_back(&g.x);
  SparseGrid<Dim>& grid = state->grid;
  grid.bin(positions);
  std::vector<size_t> reordered;
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    const std::vector<int>& slot = grid.bins(g).particle_slot;
    const size_t moved = deterministic_sum<size_t>(
        slot.size(), [&](size_t i) { return size_t(slot[i] != p.reorder_slot[i]); });
    if (double(moved) > kReorderFraction * double(slot.size())) {
      p.permute(grid.bins(g).order);
      reordered.push_back(g);
    }
  }
  if (reordered.empty()) return;
  grid.bin(positions);
  for (size_t g : reordered) {
    const std::vector<int>& slot = grid.bins(g).particle_slot;
    std::copy(slot.begin(), slot.end(), state->groups[g].reorder_slot.begin());
  }
}

template void sort_particles<2>(MpmState<2>*);
template void sort_particles<3>(MpmState<3>*);

}  // namespace tear
