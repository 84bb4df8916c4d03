// A dense window over one home block's neighbourhood: the 2^Dim blocks that its particles'
// stencils reach (the home block and its +1 neighbours, all active), as one array of
// (2 kBlock)^Dim nodes with fixed strides. A transfer copies the nodes its particles reach
// into such a window, runs their stencils there (WindowStencil: rows of consecutive entries,
// no block lookup per node), and copies sums back. Every particle-grid transfer works this way
// (mpm/'s P2G, G2P and crack fields, damage/'s phase field).
#pragma once

#include "tear/grid/sparse_grid.h"

#include <algorithm>

namespace tear {

// The window of one home block for stencils of order `Order` (<= 3): it holds the box of
// nodes that the block's particles reach, and copies node fields in and out over that box.
template <int Dim, int Order>
class BlockWindow {
 public:
  using Grid = SparseGrid<Dim>;
  static constexpr int kWidth = 2 * Grid::kBlock;  // nodes per axis: 16 in 2D, 8 in 3D
  static constexpr int kSize = Dim == 2 ? kWidth * kWidth : kWidth * kWidth * kWidth;
  static_assert(Order <= 3, "stencils wider than cubic leave the window");

  // The window of home block h of a group whose particles are at x, in the group's binning
  // order `order` (ParticleBins::order).
  template <class Positions>
  BlockWindow(const Grid& grid, const typename Grid::HomeBlock& h, const Positions& x,
              const uint32_t* order)
      : grid_(grid) {
    grid.home_neighbourhood(h.slot, &ids_, &origin_);
    reach(x, order, h.begin, h.end);
  }

  // Window coordinates (0 .. kWidth - 1 per axis) of the first node of the stencil at
  // position x (x must be in a particle of this home block).
  IVec<Dim> stencil_base(const Vec<Dim>& x) const {
    IVec<Dim> b;
    const Real inv_dx = Real(1 / grid_.dx());
    for (int d = 0; d < Dim; ++d)
      b[d] = BSpline1D<Order>::base_node((x[d] - grid_.origin()[d]) * inv_dx) + Grid::kPad -
             origin_[d];
    return b;
  }

  // Calls fn(window index, node storage index) for every node of the box.
  template <class Fn>
  void for_each_node(Fn&& fn) const {
    constexpr int kB = Grid::kBlock, kL = Grid::kLogBlock, kNpb = Grid::kNodesPerBlock;
    for (int z = (Dim == 3 ? lo_[Dim - 1] : 0); z <= (Dim == 3 ? hi_[Dim - 1] : 0); ++z)
      for (int y = lo_[1]; y <= hi_[1]; ++y) {
        const int bits = ((y >> kL) << 1) | (Dim == 3 ? (z >> kL) << 2 : 0);
        const int local = (y & (kB - 1)) << kL | (Dim == 3 ? (z & (kB - 1)) << (2 * kL) : 0);
        const int row = (Dim == 3 ? z * kWidth + y : y) * kWidth;
        for (int x = lo_[0]; x <= hi_[0]; ++x)
          fn(row + x, ids_[bits | (x >> kL)] * kNpb + local + (x & (kB - 1)));
      }
  }

  // Copies a node field's values in the box into a window array (indexed by window index),
  // or a window array's back into the node field.
  template <class T>
  void load(const std::vector<T>& field, T* window) const {
    for_each_node([&](int wn, int n) { window[wn] = field[size_t(n)]; });
  }
  template <class T>
  void store(const T* window, std::vector<T>* field) const {
    for_each_node([&](int wn, int n) { (*field)[size_t(n)] = window[wn]; });
  }

  const Grid& grid() const { return grid_; }

 private:
  // The box [lo_, hi_]: the nodes any particle of the home block can reach, or where the
  // block has few particles, the nodes these reach (a pass over their positions).
  template <class Positions>
  void reach(const Positions& x, const uint32_t* order, uint32_t begin, uint32_t end) {
    // Home-block particles have cubic base nodes 0 .. kBlock - 1, so every stencil of order
    // <= 3 lies in 0 .. kBlock + 2.
    constexpr int kReach = Grid::kBlock + std::min(Order, 2) + 1;
    constexpr int kFull = Dim == 2 ? kReach * kReach : kReach * kReach * kReach;
    if (end - begin >= uint32_t(kFull / 4)) {
      lo_.setZero(), hi_.setConstant(kReach - 1);
      return;
    }
    lo_.setConstant(kWidth), hi_.setConstant(-1);
    for (uint32_t k = begin; k < end; ++k) {
      const IVec<Dim> b = stencil_base(x[order[k]]);
      lo_ = lo_.cwiseMin(b), hi_ = hi_.cwiseMax(b);
    }
    hi_ = (hi_ + IVec<Dim>::Constant(Order)).cwiseMin(IVec<Dim>::Constant(kWidth - 1));
  }

  const Grid& grid_;
  std::array<int, Grid::kColours> ids_;  // block id of each window block (index bit d: +1 on d)
  IVec<Dim> origin_;                     // padded node coordinates of window node 0
  IVec<Dim> lo_, hi_;                    // the box of nodes the particles reach
};

// One particle's B-spline stencil in its home block's window, kept in separable form
// (per-axis weights and offsets; nothing per node is stored). visit(fn) calls fn(window
// index, w, rel) for every node with w = N_i(x_p) and rel = x_i - x_p (world units), formed on
// the fly; visit_laplacian(fn) calls fn(window index, Laplacian of N_i at x_p); with
// kSecond, visit_second(M, fn) calls fn(window index, M : grad grad N_i(x_p)) for a symmetric M
// (M = I gives the Laplacian, with other rounding). Node order: x
// fastest, as the grid's storage order would give, so that sums do not depend on the window.
// Read rel component by component (rel[c]): it is stored from scalars, and a packed read of it
// (rel as an Eigen vector operand) waits on those stores (store-forwarding stall, measured at
// 90 % of a pass).
template <int Dim, int Order, bool kSecond = false>
struct WindowStencil {
  static constexpr int kWidth = Order + 1;
  static constexpr int kW = BlockWindow<Dim, Order>::kWidth;
  Real w1[Dim][kWidth], rel1[Dim][kWidth], dd1[Dim][kWidth];  // dd1: N'' in world units
  Real dw1[kSecond ? Dim : 1][kWidth];                        // with kSecond: N' in world units

  // Inlined: called once a particle, out of line it costs 5 % of a transfer.
  __attribute__((always_inline)) WindowStencil(const BlockWindow<Dim, Order>& window,
                                               const Vec<Dim>& x) {
    const auto& grid = window.grid();
    const Real inv_dx = Real(1 / grid.dx());
    const Vec<Dim> xg = (x - grid.origin()) * inv_dx;
    const IVec<Dim> b = window.stencil_base(x);
    TEAR_ASSERT(b.minCoeff() >= 0 && b.maxCoeff() + Order < kW);  // x is of this home block
    first_ = Dim == 3 ? (b[2] * kW + b[1]) * kW + b[0] : b[1] * kW + b[0];
    for (int d = 0; d < Dim; ++d) {
      const BSpline1D<Order> s(xg[d]);
      for (int k = 0; k < kWidth; ++k) {
        w1[d][k] = s.w[k];
        rel1[d][k] = (Real(s.base + k) - xg[d]) * Real(grid.dx());
        dd1[d][k] = s.ddw[k] * inv_dx * inv_dx;
        if constexpr (kSecond) dw1[d][k] = s.dw[k] * inv_dx;
      }
    }
  }

  template <class Fn>
  void visit(Fn&& fn) const {
    for_rows([&](int row, int j, int k) {
      // A fresh vector per node: updating one component of a shared one in place makes the
      // packed loads inside fn wait on a scalar store (store-forwarding stall, 2x slower).
      if constexpr (Dim == 2) {
        for (int i = 0; i < kWidth; ++i)
          fn(row + i, w1[0][i] * w1[1][j], Vec<2>(rel1[0][i], rel1[1][j]));
      } else {
        const Real wjk = w1[1][j] * w1[2][k];
        for (int i = 0; i < kWidth; ++i)
          fn(row + i, w1[0][i] * wjk, Vec<3>(rel1[0][i], rel1[1][j], rel1[2][k]));
      }
    });
  }

  template <class Fn>
  void visit_laplacian(Fn&& fn) const {
    for_rows([&](int row, int j, int k) {
      Real wjk, ljk;
      if constexpr (Dim == 2) {
        wjk = w1[1][j], ljk = dd1[1][j];
      } else {
        wjk = w1[1][j] * w1[2][k], ljk = dd1[1][j] * w1[2][k] + w1[1][j] * dd1[2][k];
      }
      for (int i = 0; i < kWidth; ++i) fn(row + i, dd1[0][i] * wjk + w1[0][i] * ljk);
    });
  }

  template <class Fn>
  void visit_second(const Mat<Dim>& M, Fn&& fn) const {
    static_assert(kSecond, "visit_second needs WindowStencil<Dim, Order, true>");
    // M : H_i with H_i's entries products of one factor per axis (N, N' or N''): grouped by
    // the x factor, cx'' N''(x) + cx' N'(x) + cx N(x) for each row.
    for_rows([&](int row, int j, int k) {
      Real c_dd, c_dw, c_w;
      if constexpr (Dim == 2) {
        c_dd = M(0, 0) * w1[1][j];
        c_dw = 2 * M(0, 1) * dw1[1][j];
        c_w = M(1, 1) * dd1[1][j];
      } else {
        const Real wy = w1[1][j], dy = dw1[1][j], ddy = dd1[1][j];
        const Real wz = w1[2][k], dz = dw1[2][k], ddz = dd1[2][k];
        c_dd = M(0, 0) * wy * wz;
        c_dw = 2 * (M(0, 1) * dy * wz + M(0, 2) * wy * dz);
        c_w = M(1, 1) * ddy * wz + M(2, 2) * wy * ddz + 2 * M(1, 2) * dy * dz;
      }
      for (int i = 0; i < kWidth; ++i)
        fn(row + i, dd1[0][i] * c_dd + dw1[0][i] * c_dw + w1[0][i] * c_w);
    });
  }

 private:
  // fn(window index of the row's first node, j, k) for every row of nodes along x.
  template <class Fn>
  void for_rows(Fn&& fn) const {
    for (int k = 0; k < (Dim == 3 ? kWidth : 1); ++k)
      for (int j = 0; j < kWidth; ++j) fn(first_ + (Dim == 3 ? (k * kW + j) * kW : j * kW), j, k);
  }
  int first_;
};

}  // namespace tear
