// BlockWindow / WindowStencil (grid/block_window.h): a window stencil must visit the nodes of
// the particle's stencil (found here by their coordinates), with its weights, offsets and
// Laplacian weights, x fastest; the window's box of nodes must hold every stencil.
#include "tear/grid/block_window.h"

#include <gtest/gtest.h>

#include "random_points.h"

#include <random>
#include <vector>

namespace tear {
namespace {

struct Visit {
  int node;
  Real w;
  std::vector<Real> rel;
  bool operator==(const Visit& o) const { return node == o.node && w == o.w && rel == o.rel; }
};

// The stencil of order Order at x computed from scratch: nodes by coordinates (node_index),
// weights and Laplacian weights as products of 1-D B-splines (the products in the order the
// window stencil forms them, so the bits must agree), x fastest.
template <int Dim, int Order>
void reference_stencil(const SparseGrid<Dim>& g, const Vec<Dim>& x, std::vector<Visit>* visits,
                       std::vector<std::pair<int, Real>>* laplacian) {
  const Real inv_dx = Real(1 / g.dx());
  const Vec<Dim> xg = (x - g.origin()) * inv_dx;
  std::vector<BSpline1D<Order>> s;
  for (int d = 0; d < Dim; ++d) s.emplace_back(xg[d]);
  constexpr int kW = Order + 1;
  auto dd = [&](int d, int k) { return s[size_t(d)].ddw[k] * inv_dx * inv_dx; };
  for (int k = 0; k < (Dim == 3 ? kW : 1); ++k)
    for (int j = 0; j < kW; ++j)
      for (int i = 0; i < kW; ++i) {
        IVec<Dim> c;
        c[0] = s[0].base + i, c[1] = s[1].base + j;
        if constexpr (Dim == 3) c[2] = s[2].base + k;
        std::vector<Real> rel;
        const int idx[3] = {i, j, k};
        for (int d = 0; d < Dim; ++d)
          rel.push_back((Real(s[size_t(d)].base + idx[d]) - xg[d]) * Real(g.dx()));
        Real w, lap;
        if constexpr (Dim == 2) {
          w = s[0].w[i] * s[1].w[j];
          lap = dd(0, i) * s[1].w[j] + s[0].w[i] * dd(1, j);
        } else {
          const Real wjk = s[1].w[j] * s[2].w[k];
          const Real ljk = dd(1, j) * s[2].w[k] + s[1].w[j] * dd(2, k);
          w = s[0].w[i] * wjk;
          lap = dd(0, i) * wjk + s[0].w[i] * ljk;
        }
        visits->push_back({g.node_index(c), w, rel});
        laplacian->emplace_back(g.node_index(c), lap);
      }
}

// For every home block: the window's nodes map one-to-one onto grid nodes, each particle's
// window stencil visits what its grid stencil visits (same order, same bits), inside the box.
template <int Dim, int Order>
void check_windows(int particles, double lo, double hi, unsigned seed) {
  SparseGrid<Dim> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 40);
  const std::vector<Vec<Dim>> x = random_points<Dim>(particles, lo, hi, seed);
  g.bin(x);
  const ParticleBins<Dim>& b = g.bins(0);
  size_t checked = 0;
  for (const auto& h : b.home_blocks) {
    const BlockWindow<Dim, Order> window(g, h, x, b.order.data());
    std::vector<int> node_of(BlockWindow<Dim, Order>::kSize, -1);
    std::vector<int> seen(g.num_active_nodes(), 0);
    window.for_each_node([&](int wn, int n) {
      ASSERT_GE(n, 0);
      ASSERT_LT(size_t(n), g.num_active_nodes());
      EXPECT_EQ(node_of[size_t(wn)], -1);
      node_of[size_t(wn)] = n;
      EXPECT_EQ(seen[size_t(n)]++, 0);
    });
    for (uint32_t k = h.begin; k < h.end; ++k) {
      const Vec<Dim>& p = x[b.order[k]];
      std::vector<Visit> direct, windowed;
      std::vector<std::pair<int, Real>> lap_direct, lap_windowed;
      reference_stencil<Dim, Order>(g, p, &direct, &lap_direct);
      const WindowStencil<Dim, Order> st(window, p);
      st.visit([&](int wn, Real w, const Vec<Dim>& rel) {
        ASSERT_GE(wn, 0);
        ASSERT_LT(wn, (BlockWindow<Dim, Order>::kSize));
        // -1: outside the window's box.
        windowed.push_back({node_of[size_t(wn)], w, std::vector<Real>(rel.data(), rel.data() + Dim)});
      });
      ASSERT_EQ(direct.size(), windowed.size());
      for (size_t v = 0; v < direct.size(); ++v) EXPECT_TRUE(direct[v] == windowed[v]) << v;
      // The Laplacian weights too (the damage phase's gather).
      st.visit_laplacian([&](int wn, Real l) { lap_windowed.emplace_back(node_of[size_t(wn)], l); });
      EXPECT_TRUE(lap_direct == lap_windowed);
      ++checked;
    }
  }
  EXPECT_EQ(checked, x.size());
}

// Dense blocks take the whole reach of a home block, sparse ones the box of their particles.
TEST(BlockWindow, StencilsMatchTheGridsDenseBlocks2D) { check_windows<2, 2>(20000, 0.3, 0.6, 1); }
TEST(BlockWindow, StencilsMatchTheGridsDenseBlocks3D) { check_windows<3, 2>(60000, 0.3, 0.6, 2); }
TEST(BlockWindow, StencilsMatchTheGridsSparseBlocks2D) { check_windows<2, 2>(300, 0.05, 0.95, 3); }
TEST(BlockWindow, StencilsMatchTheGridsSparseBlocks3D) { check_windows<3, 2>(300, 0.05, 0.95, 4); }
TEST(BlockWindow, CubicAndLinearStencilsFitTooDense) {
  check_windows<3, 3>(60000, 0.3, 0.6, 5);
  check_windows<2, 1>(20000, 0.3, 0.6, 6);
}
TEST(BlockWindow, CubicAndLinearStencilsFitTooSparse) {
  check_windows<3, 3>(300, 0.05, 0.95, 7);
  check_windows<2, 1>(300, 0.05, 0.95, 8);
}

}  // namespace
}  // namespace tear
