// grid/: the sparse block grid (node fields live only in blocks that particles touch),
// particle binning with block colouring, and boundary conditions on grid velocities.
// Knows particles only through their positions; never sees materials or solvers.
#pragma once

#include "tear/kernels/bspline.h"
#include "tear/math/types.h"

#include <array>
#include <vector>

namespace tear {

// Nodes sit at domain_min + i dx. They are grouped in blocks of kBlock^Dim nodes (64 in 2D
// and 3D); a dense table of block slots (4 bytes a slot, one slot per block of the padded
// domain) maps a block to its node storage, which exists only for active blocks. A block is
// active when a particle's stencil can reach it.
//
// Deterministic parallel scatter: particles are binned by their "home block" (the block of
// the cubic B-spline base node, floor(x/dx) - 1); every quadratic or cubic stencil of a
// particle lies in its home block and the +1 neighbours. Home blocks of equal colour
// (parity of the block coordinates) are two blocks apart, so their writes never overlap:
// P2G runs one colour at a time (and, within a colour, one particle group at a time), blocks
// of a colour in parallel, particles of a block in ascending order. The result does not
// depend on the thread count.

// One particle group's binning: its particles grouped by home block, the home blocks by colour.
template <int Dim>
struct ParticleBins {
  static constexpr int kColours = 1 << Dim;
  struct HomeBlock {
    int slot;             // slot of the home block
    uint32_t begin, end;  // range in order
  };
  std::vector<int> particle_slot;      // home slot of each particle at binning
  std::vector<uint32_t> order;         // particle indices by home block; ascending within a block
  std::vector<HomeBlock> home_blocks;  // in slot order
  std::vector<int> colours[kColours];  // indices into home_blocks, by colour
};

template <int Dim>
class SparseGrid {
 public:
  static constexpr int kLogBlock = Dim == 2 ? 3 : 2;
  static constexpr int kBlock = 1 << kLogBlock;
  static constexpr int kNodesPerBlock = Dim == 2 ? kBlock * kBlock : kBlock * kBlock * kBlock;
  static constexpr int kPad = kBlock;  // padding nodes below node 0 in the slot table
  static constexpr int kColours = 1 << Dim;
  using HomeBlock = typename ParticleBins<Dim>::HomeBlock;

  void setup(const Vec3d& domain_min, const Vec3d& domain_max, double dx);

  // Bin the particles of every group (their positions, one array per group) by home block,
  // activate the blocks their stencils reach, and zero the node fields of the active blocks.
  // Positions must be inside the domain.
  // With `slots`, group g's home slots are (*slots)[g] (home_slot of each position, made where
  // the positions were made: G2P) instead of a pass over the positions; they are swapped into
  // bins(g).particle_slot, and the vectors left in `slots` are scratch.
  void bin(const std::vector<const std::vector<Vec<Dim>>*>& groups,
           std::vector<std::vector<int>>* slots = nullptr);
  void bin(const std::vector<Vec<Dim>>& x) { bin(std::vector<const std::vector<Vec<Dim>>*>{&x}); }
  // The slot of the home block of a particle at x inside the domain, or -1 where x is not
  // finite (bin() then refuses the positions).
  int home_slot(const Vec<Dim>& x) const {
    if (!x.allFinite()) return -1;
    const Real inv_dx = Real(1 / dx_);
    IVec<Dim> c;
    for (int d = 0; d < Dim; ++d) {
      const int base = BSpline1D<3>::base_node((x[d] - origin_[d]) * inv_dx) + kPad;
      TEAR_ASSERT(base >= 0 && base < n_nodes_[d] + 2 * kPad);
      c[d] = base >> kLogBlock;
    }
    return slot_of(c);
  }
  // Group g's binning at the last bin().
  const ParticleBins<Dim>& bins(size_t g = 0) const { return bins_[g]; }
  size_t num_groups() const { return bins_.size(); }

  double dx() const { return dx_; }
  const Vec<Dim>& origin() const { return origin_; }
  const IVec<Dim>& num_nodes() const { return n_nodes_; }  // nodes per axis of the domain
  int num_blocks() const { return int(block_slot_.size()); }
  size_t num_active_nodes() const { return block_slot_.size() * kNodesPerBlock; }

  // Unpadded integer coordinates of the node with storage index `node`.
  IVec<Dim> node_coord(int node) const;
  Vec<Dim> node_position(int node) const {
    return origin_ + node_coord(node).template cast<Real>() * Real(dx_);
  }
  // Storage index of the active node at unpadded coordinates g, or -1.
  int node_index(const IVec<Dim>& g) const;

  // The block ids of the neighbourhood of the home block at slot `home_slot` (2^Dim entries,
  // index bit d set = +1 block along axis d), and the padded node coordinates of the home
  // block origin (grid/block_window.h).
  void home_neighbourhood(int home_slot, std::array<int, kColours>* ids,
                          IVec<Dim>* home_origin) const;

  // Bytes held by the table and node fields.
  size_t memory_bytes() const;

  // For each home block of every group (hot[g][h], h indexing bins(g).home_blocks): whether a
  // home block of any group within one block along every axis is flagged in `hot`. Stencils of
  // particles whose home blocks are not near any hot one never share a node with the hot
  // particles' stencils.
  std::vector<std::vector<char>> near_hot_blocks(const std::vector<std::vector<char>>& hot) const;

  // Zero mass, velocity and velocity_old of the active blocks (bin() does; a step that is
  // redone does again).
  void zero_momentum_fields();
  // Size and zero the scalar node fields of the active blocks (bin() leaves them alone:
  // only the damage solvers use them).
  void zero_scalar_fields();
  // Size and zero the second velocity field and the crack normals of the active blocks
  // (mpm's crack fields; bin() leaves them alone). Empty vectors: no node is split.
  void zero_split_fields();
  // Empty them (no node split this step).
  void clear_split_fields() {
    mass2.clear(), velocity2.clear(), velocity_old2.clear(), crack_normal.clear();
  }
  bool split() const { return !mass2.empty(); }

  // Node fields (indexed by storage index).
  std::vector<Real> mass;
  std::vector<Vec<Dim>> velocity;      // momentum during P2G, velocity after the grid update
  std::vector<Vec<Dim>> velocity_old;  // velocity before forces (FLIP)
  std::vector<Real> scalar;            // a transferred scalar (damage d_i)
  std::vector<Real> scalar_weight;     // its weights (sum_p w_ip)
  // Crack fields (damage-gradient partitioning): a node where a crack passes holds a second
  // velocity field for the particles whose damage gradient opposes its crack normal (a zero
  // normal: the node is not split).
  std::vector<Real> mass2;
  std::vector<Vec<Dim>> velocity2, velocity_old2;
  std::vector<Vec<Dim>> crack_normal;

 private:
  int slot_of(const IVec<Dim>& b) const {
    int s = b[Dim - 1];
    for (int d = Dim - 2; d >= 0; --d) s = s * n_slots_[d] + b[d];
    return s;
  }
  IVec<Dim> slot_coord(int slot) const;
  // Whether slots[g] equals bins(g).particle_slot for every group g.
  bool same_slots(const std::vector<std::vector<int>>& slots) const;

  double dx_ = 1;
  Vec<Dim> origin_ = Vec<Dim>::Zero();
  IVec<Dim> n_nodes_ = IVec<Dim>::Zero();
  IVec<Dim> n_slots_ = IVec<Dim>::Zero();
  std::vector<int> table_;               // slot -> block id or -1
  std::vector<int> block_slot_;          // block id -> slot
  std::vector<uint32_t> counts_;         // per slot scratch of bin() (0 between calls)
  bool binned_ = false;                  // bins_ and the active blocks hold a finished bin()
  std::vector<ParticleBins<Dim>> bins_;  // per group
};

// ---- inline definitions (hot path) ----

template <int Dim>
inline void SparseGrid<Dim>::home_neighbourhood(int s0, std::array<int, kColours>* ids,
                                                IVec<Dim>* home_origin) const {
  const IVec<Dim> b = slot_coord(s0);
  for (int d = 0; d < Dim; ++d) (*home_origin)[d] = b[d] << kLogBlock;
  int stride[Dim];
  stride[0] = 1;
  for (int d = 1; d < Dim; ++d) stride[d] = stride[d - 1] * n_slots_[d - 1];
  for (int c = 0; c < kColours; ++c) {
    int s = s0;
    for (int d = 0; d < Dim; ++d) s += ((c >> d) & 1) * stride[d];
    (*ids)[c] = table_[s];
  }
}

}  // namespace tear
