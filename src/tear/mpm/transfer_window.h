// The node fields P2G and G2P work on, copied into a BlockWindow (grid/block_window.h) around
// one home block, each node's values side by side in lanes (math/lanes.h), so that a node's
// update in a stencil is a few whole-register operations with the same roundings as the scalar
// ones: ScatterWindow (P2G) holds mass and momentum, GatherWindow (G2P) velocities; with FLIP
// the force-free ones too, with crack fields the second field's and the crack normals.
#pragma once

#include "tear/grid/block_window.h"
#include "tear/math/lanes.h"
#include "tear/mpm/phases.h"

#include <vector>

namespace tear {

// P2G's window: per node and field, lanes (m, p_x, p_y[, p_z]) (the fourth lane unused in
// 2D) and, with FLIP, the force-free momentum in the same lanes (lane 0 not copied).
template <int Dim, bool kFlip, bool kSplit>
struct ScatterWindow {
  using Window = BlockWindow<Dim, kTransferOrder>;
  using Node = Lanes<4>;
  static constexpr int kFields = kSplit ? 2 : 1;
  std::vector<Node> mass_momentum[kFields], momentum_old[kFields];
  std::vector<Vec<Dim>> normal;

  ScatterWindow() {
    for (int f = 0; f < kFields; ++f) {
      mass_momentum[f].resize(Window::kSize);
      momentum_old[f].resize(kFlip ? Window::kSize : 0);
    }
    if (kSplit) normal.resize(Window::kSize);
  }

  // Copies the box's masses and momenta (and crack normals) in. Raw pointers taken once:
  // through the vectors, every node's copy reloads their data pointers (the stores could
  // alias them as far as the compiler knows).
  void load(const SparseGrid<Dim>& grid, const Window& window) {
    for (int f = 0; f < kFields; ++f) {
      Node* const mp = mass_momentum[f].data();
      Node* const old = momentum_old[f].data();
      const Real* const gm = (f == 0 ? grid.mass : grid.mass2).data();
      const Vec<Dim>* const gv = (f == 0 ? grid.velocity : grid.velocity2).data();
      const Vec<Dim>* const gv_old = (f == 0 ? grid.velocity_old : grid.velocity_old2).data();
      window.for_each_node([&](int wn, int n) {
        Node& a = mp[wn];
        a[0] = gm[n];
        for (int d = 0; d < Dim; ++d) a[1 + d] = gv[n][d];
        if constexpr (Dim == 2) a[3] = 0;
        if constexpr (kFlip)
          for (int d = 0; d < Dim; ++d) old[wn][1 + d] = gv_old[n][d];
      });
    }
    if constexpr (kSplit) window.load(grid.crack_normal, normal.data());
  }

  // Copies the box's masses and momenta back out.
  void store(SparseGrid<Dim>* grid, const Window& window) const {
    for (int f = 0; f < kFields; ++f) {
      const Node* const mp = mass_momentum[f].data();
      const Node* const old = momentum_old[f].data();
      Real* const gm = (f == 0 ? grid->mass : grid->mass2).data();
      Vec<Dim>* const gv = (f == 0 ? grid->velocity : grid->velocity2).data();
      Vec<Dim>* const gv_old = (f == 0 ? grid->velocity_old : grid->velocity_old2).data();
      window.for_each_node([&](int wn, int n) {
        gm[n] = mp[wn][0];
        for (int d = 0; d < Dim; ++d) gv[n][d] = mp[wn][1 + d];
        if constexpr (kFlip)
          for (int d = 0; d < Dim; ++d) gv_old[n][d] = old[wn][1 + d];
      });
    }
  }
};

// G2P's window: per node and field the velocity (and with FLIP the force-free one) in lanes
// 0 .. Dim - 1 (a fourth lane, zero, in 3D); crack normals with crack fields.
template <int Dim, bool kFlip, bool kSplit>
struct GatherWindow {
  using Window = BlockWindow<Dim, kTransferOrder>;
  static constexpr int kLanes = Dim == 2 ? 2 : 4;
  using Node = Lanes<kLanes>;
  static constexpr int kFields = kSplit ? 2 : 1;
  std::vector<Node> velocity[kFields], velocity_old[kFields];
  std::vector<Vec<Dim>> normal;

  GatherWindow() {
    for (int f = 0; f < kFields; ++f) {
      velocity[f].resize(Window::kSize);
      velocity_old[f].resize(kFlip ? Window::kSize : 0);
    }
    if (kSplit) normal.resize(Window::kSize);
  }

  void load(const SparseGrid<Dim>& grid, const Window& window) {
    for (int f = 0; f < kFields; ++f) {
      Node* const v = velocity[f].data();
      Node* const v_old = velocity_old[f].data();
      const Vec<Dim>* const gv = (f == 0 ? grid.velocity : grid.velocity2).data();
      const Vec<Dim>* const gv_old = (f == 0 ? grid.velocity_old : grid.velocity_old2).data();
      window.for_each_node([&](int wn, int n) {
        for (int d = 0; d < Dim; ++d) v[wn][d] = gv[n][d];
        if constexpr (kFlip)
          for (int d = 0; d < Dim; ++d) v_old[wn][d] = gv_old[n][d];
      });
    }
    if constexpr (kSplit) window.load(grid.crack_normal, normal.data());
  }
};

}  // namespace tear
