// The crack-field phase: damage-gradient partitioning of the grid (after Homel & Herbold 2017,
// "Field-gradient partitioning for fracture and frictional contact in the material point
// method"). With one velocity per node, a node within reach of both faces of a crack moves
// them together, so particles beside a crack whose faces slide are sheared until they crack
// too and the band widens. Here such a node holds one velocity field per side.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
void partition_crack_fields(const MpmSettings& settings, MpmState<Dim>* state) {
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
  grid.zero_scalar_fields();
  grid.zero_split_fields();
  // The damage on the grid, mass-weighted: d_i = sum_p w m d / sum_p w m.
  scatter_particles(*state, [&](size_t g, uint32_t i) {
    const Particles<Dim>& p = state->groups[g];
    const Real md = p.mass[i] * p.damage[i];
    Stencil<Dim, kTransferOrder>(grid, p.x[i]).visit([&](int node, Real w, const Vec<Dim>&) {
      grid.scalar[node] += w * md;
      grid.scalar_weight[node] += w * p.mass[i];
    });
  });
  parallel_for(grid.num_active_nodes(), [&](size_t node) {
    if (grid.scalar_weight[node] > 0) grid.scalar[node] /= grid.scalar_weight[node];
    grid.scalar_weight[node] = 0;
  });
  // Each particle's damage gradient, the MLS estimate grad d = D^-1 sum_i w d_i (x_i - x_p)
  // (as APIC estimates the velocity gradient). Beside a crack it points towards the crack,
  // from either side, so its sign against a node's normal tells the sides apart.
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  for (Particles<Dim>& p : state->groups) {
    parallel_for(p.size(), [&](size_t i) {
      Vec<Dim> grad = Vec<Dim>::Zero();
      Stencil<Dim, kTransferOrder>(grid, p.x[i]).visit([&](int node, Real w, const Vec<Dim>& rel) {
        grad += (w * grid.scalar[node]) * rel;
      });
      p.damage_gradient[i] = inv_d * grad;
    });
  }
  // Each node's crack normal: the steepest particle gradient in reach (strictly steeper
  // replaces, in the scatter's fixed order), kept where a particle in reach has damage
  // >= split_damage; mass2 holds the steepest squared gradient meanwhile and scalar_weight
  // the largest damage.
  scatter_particles(*state, [&](size_t g, uint32_t i) {
    const Particles<Dim>& p = state->groups[g];
    const Vec<Dim>& grad = p.damage_gradient[i];
    const Real steep = grad.squaredNorm(), d = p.damage[i];
    Stencil<Dim, kTransferOrder>(grid, p.x[i]).visit([&](int node, Real, const Vec<Dim>&) {
      if (steep > grid.mass2[node]) grid.mass2[node] = steep, grid.crack_normal[node] = grad;
      grid.scalar_weight[node] = std::max(grid.scalar_weight[node], d);
    });
  });
  parallel_for(grid.num_active_nodes(), [&](size_t node) {
    if (grid.scalar_weight[node] < split) grid.crack_normal[node].setZero();
    grid.mass2[node] = 0;
  });
}

template void partition_crack_fields<2>(const MpmSettings&, MpmState<2>*);
template void partition_crack_fields<3>(const MpmSettings&, MpmState<3>*);

}  // namespace tear
