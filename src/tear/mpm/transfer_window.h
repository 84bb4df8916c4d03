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
  // the masses too. Raw pointers taken once: through the vectors, every node's copy reloads
  // their data pointers (the stores could alias them as far as the compiler knows).
  template <bool kMass>
  void load(const SparseGrid<Dim>& grid, const Window& window) {
    for (int f = 0; f < kFields; ++f) {
      Real* const m = field[f].m.data();
      Vec<Dim>* const v = field[f].v.data();
      Vec<Dim>* const v_old = field[f].v_old.data();
      const Real* const gm = (f == 0 ? grid.mass : grid.mass2).data();
      const Vec<Dim>* const gv = (f == 0 ? grid.velocity : grid.velocity2).data();
      const Vec<Dim>* const gv_old = (f == 0 ? grid.velocity_old : grid.velocity_old2).data();
      window.for_each_node([&](int wn, int n) {
        if constexpr (kMass) m[wn] = gm[n];
        v[wn] = gv[n];
        if constexpr (kFlip) v_old[wn] = gv_old[n];
      });
    }
    if constexpr (kSplit) window.load(grid.crack_normal, normal.data());
  }

  // Copies masses and velocities of the box back out.
  void store(SparseGrid<Dim>* grid, const Window& window) const {
    for (int f = 0; f < kFields; ++f) {
      const Real* const m = field[f].m.data();
      const Vec<Dim>* const v = field[f].v.data();
      const Vec<Dim>* const v_old = field[f].v_old.data();
      Real* const gm = (f == 0 ? grid->mass : grid->mass2).data();
      Vec<Dim>* const gv = (f == 0 ? grid->velocity : grid->velocity2).data();
      Vec<Dim>* const gv_old = (f == 0 ? grid->velocity_old : grid->velocity_old2).data();
      window.for_each_node([&](int wn, int n) {
        gm[n] = m[wn];
        gv[n] = v[wn];
        if constexpr (kFlip) gv_old[n] = v_old[wn];
      });
    }
  }
};

}  // namespace tear
