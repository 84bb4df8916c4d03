// The crack-field phase: damage-gradient partitioning of the grid (after Homel & Herbold 2017,
// "Field-gradient partitioning for fracture and frictional contact in the material point
// method"). With one velocity per node, a node within reach of both faces of a crack moves
// them together, so particles beside a crack whose faces slide are sheared until they crack
// too and the band widens. Here such a node holds one velocity field per side.
#include "tear/damage/phase_field.h"
#include "tear/exec/parallel.h"
#include "tear/grid/block_window.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
void partition_crack_fields(const MpmSettings& settings, MpmState<Dim>* state, Domain& domain) {
  SparseGrid<Dim>& grid = state->grid;
  // Until some particle reaches split_damage no node is split (damage never decreases): the
  // grid keeps no second field and P2G, the grid update and G2P take their one-field paths.
  const Real split = Real(settings.damage.split_damage);
  bool cracked = false;
  for (const Particles<Dim>& p : state->groups)
    cracked = cracked || parallel_any(p.size(), [&](size_t i) { return p.damage[i] >= split; });
  if (!cracked) {
    grid.clear_split_fields();
    return;
  }
  grid.zero_split_fields();
  // The damage on the grid (as the damage update makes it, with its halos, but with the
  // transfer's quadratic kernel: the cubic one's wider reach blurs the gradient's sign beside
  // a crack, bands half a spacing wider); scalar_weight is reused below.
  // Away from the blocks near damage the field is 0 and so is every gradient: the passes below
  // skip those blocks (the same result, at the cost of the damaged region only).
  const std::vector<std::vector<char>> near =
      damage_on_grid<kTransferOrder>(state->groups, &grid, domain);
  parallel_for(grid.num_active_nodes(), [&](size_t node) { grid.scalar_weight[node] = 0; });
  // Every pass works home block by home block in a window of the nodes its particles reach
  // (grid/block_window.h): the same operations in the same order as on the grid.
  using HomeBlock = typename SparseGrid<Dim>::HomeBlock;
  using Window = BlockWindow<Dim, kTransferOrder>;
  constexpr size_t kSize = Window::kSize;
  // Each particle's damage gradient, the MLS estimate grad d = D^-1 sum_i w d_i (x_i - x_p)
  // (as APIC estimates the velocity gradient). Beside a crack it points towards the crack,
  // from either side, so its sign against a node's normal tells the sides apart.
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    const ParticleBins<Dim>& bins = grid.bins(g);
    parallel_for(bins.home_blocks.size(), [&](size_t b) {
      const HomeBlock& h = bins.home_blocks[b];
      if (!near[g][b]) {
        for (uint32_t k = h.begin; k < h.end; ++k) p.damage_gradient[bins.order[k]].setZero();
        return;
      }
      const Window window(grid, h, p.x, bins.order.data());
      thread_local std::vector<Real> value(kSize);
      window.load(grid.scalar, value.data());
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t i = bins.order[k];
        Vec<Dim> grad = Vec<Dim>::Zero();
        WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit([&](int wn, Real w,
                                                                     const Vec<Dim>& rel) {
          // Component by component: rel is built from scalars, and reading it as a packed
          // pair waits on those stores (store forwarding: 9 of 10 samples of this pass).
          const Real wd = w * value[size_t(wn)];
          for (int c = 0; c < Dim; ++c) grad[c] += wd * rel[c];
        });
        p.damage_gradient[i] = inv_d * grad;
      }
    });
  }
  // Each node's crack normal: the steepest particle gradient in reach (strictly steeper
  // replaces, in the scatter's fixed order), kept where a particle in reach has damage
  // >= split_damage; mass2 holds the steepest squared gradient meanwhile and scalar_weight
  // the largest damage.
  scatter_home_blocks(*state, [&](size_t g, const HomeBlock& h) {
    // Undamaged particles with zero gradients: nothing to take the steepest of.
    if (!near[g][size_t(&h - grid.bins(g).home_blocks.data())]) return;
    const Particles<Dim>& p = state->groups[g];
    const uint32_t* order = grid.bins(g).order.data();
    const Window window(grid, h, p.x, order);
    thread_local std::vector<Real> steepest(kSize), most(kSize);
    thread_local std::vector<Vec<Dim>> normal(kSize);
    window.load(grid.mass2, steepest.data());
    window.load(grid.scalar_weight, most.data());
    window.load(grid.crack_normal, normal.data());
    for (uint32_t k = h.begin; k < h.end; ++k) {
      const uint32_t i = order[k];
      const Vec<Dim>& grad = p.damage_gradient[i];
      const Real steep = grad.squaredNorm(), d = p.damage[i];
      WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit([&](int wn, Real,
                                                                   const Vec<Dim>&) {
        const size_t n = size_t(wn);
        if (steep > steepest[n]) steepest[n] = steep, normal[n] = grad;
        most[n] = std::max(most[n], d);
      });
    }
    window.store(steepest.data(), &grid.mass2);
    window.store(most.data(), &grid.scalar_weight);
    window.store(normal.data(), &grid.crack_normal);
  });
  // Across ranks: an owned node takes the steepest of its ghost copies' normals and the largest
  // damage; after the split decision every ghost gets its owner's normal (P2G and G2P read it).
  const size_t n = grid.num_active_nodes();
  const NodeFieldView normals = node_field(grid.crack_normal.data()->data(), n, Dim);
  domain.max_halos(node_field(grid.mass2.data(), n, 1), {normals},
                   {node_field(grid.scalar_weight.data(), n, 1)});
  parallel_for(n, [&](size_t node) {
    if (grid.scalar_weight[node] < split) grid.crack_normal[node].setZero();
    grid.mass2[node] = 0;
  });
  domain.copy_halos({normals});
}

template void partition_crack_fields<2>(const MpmSettings&, MpmState<2>*, Domain&);
template void partition_crack_fields<3>(const MpmSettings&, MpmState<3>*, Domain&);

}  // namespace tear
