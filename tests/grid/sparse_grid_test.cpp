#include "tear/grid/sparse_grid.h"
#include "tear/grid/block_window.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "random_points.h"

#include <random>
#include <set>

namespace tear {
namespace {

// The stencil of order Order at particle i of x (group 0 of g), through the window of its
// home block (grid/block_window.h), with grid storage indices.
template <int Dim, int Order>
struct HomeStencil {
  using Window = BlockWindow<Dim, Order>;
  HomeStencil(const SparseGrid<Dim>& g, const std::vector<Vec<Dim>>& x, uint32_t i)
      : index(i),
        window(g, {g.bins(0).particle_slot[i], 0, 1}, x, &index),
        stencil(window, x[i]) {
    window.for_each_node([&](int wn, int n) { node_of[size_t(wn)] = n; });
  }
  template <class Fn>
  void visit(Fn&& fn) const {
    stencil.visit([&](int wn, Real w, const Vec<Dim>& rel) { fn(node_of[size_t(wn)], w, rel); });
  }
  template <class Fn>
  void visit_laplacian(Fn&& fn) const {
    stencil.visit_laplacian([&](int wn, Real l) { fn(node_of[size_t(wn)], l); });
  }
  template <class Fn>
  void visit_second(const Mat<Dim>& M, Fn&& fn) const {
    stencil.visit_second(M, [&](int wn, Real l) { fn(node_of[size_t(wn)], l); });
  }
  uint32_t index;  // the window's one particle
  Window window;
  WindowStencil<Dim, Order, true> stencil;
  std::array<int, Window::kSize> node_of;
};

template <int Dim>
void check_binning() {
  SparseGrid<Dim> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 64);
  auto x = random_points<Dim>(5000, 0.3, 0.6, 3);
  g.bin(x);
  // order is a permutation grouped by home block, ascending inside each block.
  const ParticleBins<Dim>& b = g.bins(0);
  std::vector<int> seen(x.size(), 0);
  for (auto& h : b.home_blocks)
    for (uint32_t k = h.begin; k < h.end; ++k) {
      ++seen[b.order[k]];
      EXPECT_EQ(b.particle_slot[b.order[k]], h.slot);
      if (k > h.begin) {
        EXPECT_LT(b.order[k - 1], b.order[k]);
      }
    }
  for (int s : seen) EXPECT_EQ(s, 1);
  // Every stencil node of every particle is active and maps back to its coordinates.
  for (size_t i = 0; i < x.size(); ++i) {
    const Vec<Dim>& p = x[i];
    int visited = 0;
    HomeStencil<Dim, 3>(g, x, uint32_t(i)).visit([&](int node, Real, const Vec<Dim>& rel) {
      ASSERT_GE(node, 0);
      const Vec<Dim> xi = g.node_position(node);
      EXPECT_TRUE((xi - p - rel).norm() < 1e-12);
      EXPECT_EQ(g.node_index(g.node_coord(node)), node);
      ++visited;
    });
    EXPECT_EQ(visited, Dim == 2 ? 16 : 64);
  }
  // Same-colour home blocks are at least two blocks apart on some axis.
  size_t total = 0;
  for (int c = 0; c < SparseGrid<Dim>::kColours; ++c) total += b.colours[c].size();
  EXPECT_EQ(total, b.home_blocks.size());
  // Memory follows the occupied region: far fewer nodes than the dense 65^Dim domain.
  EXPECT_LT(g.num_active_nodes(), size_t(std::pow(65.0, Dim)) / 2);
}

TEST(SparseGrid, BinningIsAStableGroupingAndStencilsAreActive2D) { check_binning<2>(); }
TEST(SparseGrid, BinningIsAStableGroupingAndStencilsAreActive3D) { check_binning<3>(); }

// Several particle groups: each is binned on its own, and the active blocks are those of all of
// them together (the same as binning every particle as one group).
template <int Dim>
void check_group_binning() {
  auto a = random_points<Dim>(3000, 0.2, 0.5, 3), b = random_points<Dim>(2000, 0.45, 0.8, 4);
  SparseGrid<Dim> two, one;
  two.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 64);
  one.setup(Vec3d::Zero(), Vec3d::Ones(), 1.0 / 64);
  two.bin(std::vector<const std::vector<Vec<Dim>>*>{&a, &b});
  std::vector<Vec<Dim>> all = a;
  all.insert(all.end(), b.begin(), b.end());
  one.bin(all);
  ASSERT_EQ(two.num_groups(), 2u);
  EXPECT_EQ(two.num_active_nodes(), one.num_active_nodes());
  for (int blk = 0; blk < one.num_blocks(); ++blk) {
    const int node = blk * SparseGrid<Dim>::kNodesPerBlock;
    EXPECT_EQ(two.node_index(one.node_coord(node)), node);
  }
  EXPECT_EQ(two.bins(0).order.size(), a.size());
  EXPECT_EQ(two.bins(1).order.size(), b.size());
  for (size_t i = 0; i < b.size(); ++i)
    EXPECT_EQ(two.bins(1).particle_slot[i], one.bins(0).particle_slot[a.size() + i]);
  // near_hot_blocks sees across groups: a hot block of group 0 makes group 1's neighbours near.
  std::vector<std::vector<char>> hot = {std::vector<char>(two.bins(0).home_blocks.size(), 1),
                                        std::vector<char>(two.bins(1).home_blocks.size(), 0)};
  const auto near = two.near_hot_blocks(hot);
  size_t near1 = 0;
  for (char c : near[1]) near1 += c;
  EXPECT_GT(near1, 0u);
  EXPECT_LT(near1, near[1].size());
}

TEST(SparseGrid, GroupsAreBinnedApartOverOneActivation2D) { check_group_binning<2>(); }
TEST(SparseGrid, GroupsAreBinnedApartOverOneActivation3D) { check_group_binning<3>(); }

TEST(SparseGrid, StencilWeightsReproduceConstantsLinesAndTheMlsInertia) {
  SparseGrid<3> g;
  g.setup(Vec3d::Zero(), Vec3d::Ones(), 0.05);
  auto x = random_points<3>(100, 0.2, 0.8, 5);
  g.bin(x);
  for (size_t i = 0; i < x.size(); ++i) {
    for (int order : {2, 3}) {
      double sw = 0, slap = 0;
      Vec<3> swx = Vec<3>::Zero();
      Mat<3> swxx = Mat<3>::Zero();
      auto add = [&](int, Real w, const Vec<3>& rel) {
        sw += w, swx += w * rel, swxx += w * rel * rel.transpose();
      };
      if (order == 2) {
        HomeStencil<3, 2>(g, x, uint32_t(i)).visit(add);
      } else {
        const HomeStencil<3, 3> st(g, x, uint32_t(i));
        st.visit(add);
        st.visit_laplacian([&](int, Real lap_w) { slap += lap_w; });
        EXPECT_LT(std::abs(slap), 1e-9 / (0.05 * 0.05));  // Laplacian of a constant
      }
      EXPECT_NEAR(sw, 1, 1e-13);
      EXPECT_LT(swx.norm(), 1e-13);  // linear reproduction: sum w (x_i - x_p) = 0
      // sum w (x_i - x_p)(x_i - x_p)^T = dx^2 / kInvD I: the MLS-MPM inertia (4, resp. 3).
      const double inv_d = order == 2 ? 4 : 3;
      EXPECT_LT((swxx - Mat<3>::Identity() * (0.05 * 0.05 / inv_d)).norm(), 1e-15);
    }
  }
}

}  // namespace
}  // namespace tear

namespace tear {
namespace {

// A grid of spacing dx over the unit box with the points x binned and its scalar fields zeroed.
template <int Dim>
void bin_points(SparseGrid<Dim>* g, double dx, const std::vector<Vec<Dim>>& x) {
  g->setup(Vec3d::Zero(), Vec3d::Ones(), dx);
  g->bin(x);
  g->zero_scalar_fields();
}

// The grid's scalar field set to f at every node.
template <int Dim, class Field>
void sample_on_nodes(SparseGrid<Dim>* g, Field&& f) {
  for (size_t i = 0; i < g->scalar.size(); ++i) g->scalar[i] = Real(f(g->node_position(int(i))));
}

// The cubic-kernel Laplacian of a smooth field sampled on the grid nodes, evaluated at
// particles: exact for quadratics (the cubic B-spline reproduces them up to a constant
// shift, which the Laplacian removes) and second-order accurate for a cosine.
template <int Dim>
void check_laplacian() {
  std::vector<double> errors;
  for (double dx : {1.0 / 32, 1.0 / 64}) {
    SparseGrid<Dim> g;
    const auto x = random_points<Dim>(300, 0.3, 0.7, 11);
    bin_points(&g, dx, x);
    auto quadratic = [](const Vec<Dim>& p) { return 3 * p[0] * p[0] - p[0] * p[1] + 2 * p[1] * p[1]; };
    auto wave = [](const Vec<Dim>& p) { return std::cos(4 * p[0]) * std::cos(3 * p[1]); };
    for (int field = 0; field < 2; ++field) {
      sample_on_nodes(&g, [&](const Vec<Dim>& p) { return field == 0 ? quadratic(p) : wave(p); });
      double worst = 0;
      for (size_t i = 0; i < x.size(); ++i) {
        const Vec<Dim>& p = x[i];
        double lap = 0;
        HomeStencil<Dim, 3>(g, x, uint32_t(i)).visit_laplacian(
            [&](int node, Real lap_w) { lap += lap_w * g.scalar[node]; });
        const double exact = field == 0 ? 10.0 : -25.0 * wave(p);
        worst = std::max(worst, std::abs(lap - exact));
      }
      if (field == 0) {
        EXPECT_LT(worst, 1e-8) << "quadratic, dx " << dx;
      } else {
        errors.push_back(worst);
      }
    }
  }
  // Halving dx divides the error by about 4.
  EXPECT_LT(errors[0], 0.1);  // 0.4% of max|Lap f| = 25 at dx = 1/32
  EXPECT_GT(errors[0] / errors[1], 3.0);
}

TEST(Stencil, CubicLaplacianIsExactForQuadraticsAndSecondOrder2D) { check_laplacian<2>(); }
TEST(Stencil, CubicLaplacianIsExactForQuadraticsAndSecondOrder3D) { check_laplacian<3>(); }

// M : grad grad f (the anisotropic crack surface term) from the cubic kernel, for random
// symmetric M with off-diagonal entries: exact for any quadratic x^T Q x / 2 + b.x (tr(M Q),
// cross terms included), equal to the Laplacian for M = I, and second-order accurate for a
// plane wave cos(k.x), whose exact value is -(k^T M k) cos(k.x).
template <int Dim>
void check_second_derivatives() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  Mat<Dim> Q, M;
  for (int a = 0; a < Dim; ++a)
    for (int b = 0; b <= a; ++b) {
      Q(a, b) = Q(b, a) = Real(3 * u(rng));
      M(a, b) = M(b, a) = Real(u(rng));
    }
  M += Real(2) * Mat<Dim>::Identity();
  Vec<Dim> b_lin, k;
  for (int a = 0; a < Dim; ++a) b_lin[a] = Real(u(rng)), k[a] = Real(2 + a + u(rng));
  const double exact_quadratic = double((M * Q).trace());
  std::vector<double> errors;
  for (double dx : {1.0 / 32, 1.0 / 64}) {
    SparseGrid<Dim> g;
    const auto x = random_points<Dim>(300, 0.3, 0.7, 13);
    bin_points(&g, dx, x);
    auto quadratic = [&](const Vec<Dim>& p) { return 0.5 * p.dot(Q * p) + b_lin.dot(p); };
    auto wave = [&](const Vec<Dim>& p) { return std::cos(double(k.dot(p))); };
    for (int field = 0; field < 2; ++field) {
      sample_on_nodes(&g, [&](const Vec<Dim>& p) { return field == 0 ? quadratic(p) : wave(p); });
      double worst = 0, worst_identity = 0;
      for (size_t i = 0; i < x.size(); ++i) {
        const HomeStencil<Dim, 3> st(g, x, uint32_t(i));
        double second = 0, lap = 0, identity = 0;
        st.visit_second(M, [&](int node, Real w) { second += w * g.scalar[node]; });
        st.visit_second(Mat<Dim>::Identity(),
                        [&](int node, Real w) { identity += w * g.scalar[node]; });
        st.visit_laplacian([&](int node, Real w) { lap += w * g.scalar[node]; });
        const double exact = field == 0 ? exact_quadratic : -double(k.dot(M * k)) * wave(x[i]);
        worst = std::max(worst, std::abs(second - exact));
        worst_identity = std::max(worst_identity, std::abs(identity - lap));
      }
      EXPECT_LT(worst_identity, 1e-8) << "M = I against the Laplacian, field " << field;
      if (field == 0) {
        EXPECT_LT(worst, 1e-8) << "quadratic, dx " << dx;
      } else {
        errors.push_back(worst);
      }
    }
  }
  EXPECT_LT(errors[0], 0.02 * std::abs(double(k.dot(M * k))));
  EXPECT_GT(errors[0] / errors[1], 3.0);  // second order
}

TEST(Stencil, CubicSecondDerivativesAreExactForQuadraticsAndSecondOrder2D) {
  check_second_derivatives<2>();
}
TEST(Stencil, CubicSecondDerivativesAreExactForQuadraticsAndSecondOrder3D) {
  check_second_derivatives<3>();
}

}  // namespace
}  // namespace tear
