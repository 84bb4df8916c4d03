// The node fields P2G and G2P work on, copied into a BlockWindow (grid/block_window.h) around
// one home block: mass, velocity (momentum during P2G) and, for FLIP, the force-free one; with
// crack fields the second field's too and the crack normals. Laid out as the grid's fields
// (one array per field: interleaved, the compiler packs neighbouring nodes and stalls).
#pragma once

#include "tear/grid/block_window.h"
#include "tear/mpm/phases.h"

#include <vector>

namespace tear {

template <int Dim, bool kFlip, bool kSplit>
struct TransferWindow {
  using Window = BlockWindow<Dim, kTransferOrder>;
  static constexpr int kFields = kSplit ? 2 : 1;
  struct Field {
    std::vector<Real> m;
    std::vector<Vec<Dim>> v, v_old;
  } field[kFields];
  std::vector<Vec<Dim>> normal;

  TransferWindow() {
    constexpr size_t n = Window::kSize;
    for (Field& f : field) f.m.resize(n), f.v.resize(n), f.v_old.resize(kFlip ? n : 0);
    if (kSplit) normal.resize(n);
  }

  // Copies the nodes of the window's box in: velocities (and crack normals), and with kMass
  // the masses too.
  template <bool kMass>
  void load(const SparseGrid<Dim>& grid, const Window& window) {
    window.for_each_node([&](int wn, int n) {
      for (int f = 0; f < kFields; ++f) {
        Field& w = field[f];
        if constexpr (kMass) w.m[wn] = f == 0 ? grid.mass[n] : grid.mass2[n];
        w.v[wn] = f == 0 ? grid.velocity[n] : grid.velocity2[n];
        if constexpr (kFlip) w.v_old[wn] = f == 0 ? grid.velocity_old[n] : grid.velocity_old2[n];
      }
      if constexpr (kSplit) normal[size_t(wn)] = grid.crack_normal[n];
    });
  }

  // Copies masses and velocities of the box back out.
  void store(SparseGrid<Dim>* grid, const Window& window) const {
    window.for_each_node([&](int wn, int n) {
      for (int f = 0; f < kFields; ++f) {
        const Field& w = field[f];
        (f == 0 ? grid->mass[n] : grid->mass2[n]) = w.m[wn];
        (f == 0 ? grid->velocity[n] : grid->velocity2[n]) = w.v[wn];
        if constexpr (kFlip)
          (f == 0 ? grid->velocity_old[n] : grid->velocity_old2[n]) = w.v_old[wn];
      }
    });
  }
};

}  // namespace tear
