// The sort phase: particles binned by grid block every step, reordered in memory now and then.
#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

#include <algorithm>

namespace tear {

namespace {
// Reorder a group in memory when this fraction changed home block since its last reorder.
constexpr double kReorderFraction = 0.1;
}  // namespace

template <int Dim>
void sort_particles(MpmState<Dim>* state) {
  // Codimensional element particles are not binned: their vertices carry them (codim/).
  static const std::vector<Vec<Dim>> kNone;
  std::vector<const std::vector<Vec<Dim>>*> positions;
  for (const Particles<Dim>& g : state->groups)
    positions.push_back(element_dimension(g.kind) > 0 ? &kNone : &g.x);
  SparseGrid<Dim>& grid = state->grid;
  // G2P's home slots where they describe these positions (no pass over the positions).
  const bool made = state->home_slots_step == state->steps;
  state->home_slots_step = -1;
  grid.bin(positions, made ? &state->home_slots : nullptr);
  std::vector<size_t> reordered;
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    if (p.codimensional()) continue;  // elements refer to vertices by index: never reordered
    const std::vector<int>& slot = grid.bins(g).particle_slot;
    const size_t moved = deterministic_sum<size_t>(
        slot.size(), [&](size_t i) { return size_t(slot[i] != p.reorder_slot[i]); });
    if (double(moved) > kReorderFraction * double(slot.size())) {
      p.permute(grid.bins(g).order);
      reordered.push_back(g);
    }
  }
  if (reordered.empty()) return;
  // The slots of the reordered groups in their new order (the others' as they are).
  state->home_slots.resize(state->groups.size());
  for (size_t g = 0; g < state->groups.size(); ++g) {
    const std::vector<int>& slot = grid.bins(g).particle_slot;
    std::vector<int>& next = state->home_slots[g];
    reserve_large(&next, slot.size());
    next.resize(slot.size());
    const bool moved = std::find(reordered.begin(), reordered.end(), g) != reordered.end();
    const uint32_t* order = grid.bins(g).order.data();
    parallel_for(slot.size(), [&](size_t k) { next[k] = slot[moved ? order[k] : k]; });
  }
  grid.bin(positions, &state->home_slots);
  for (size_t g : reordered) {
    const std::vector<int>& slot = grid.bins(g).particle_slot;
    std::copy(slot.begin(), slot.end(), state->groups[g].reorder_slot.begin());
  }
}

template void sort_particles<2>(MpmState<2>*);
template void sort_particles<3>(MpmState<3>*);

}  // namespace tear
