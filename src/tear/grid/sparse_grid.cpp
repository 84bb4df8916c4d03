#include "tear/grid/sparse_grid.h"

#include <atomic>
#include <stdexcept>

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"

#include <algorithm>
#include <cmath>

namespace tear {

template <int Dim>
void SparseGrid<Dim>::setup(const Vec3d& domain_min, const Vec3d& domain_max, double dx) {
  dx_ = dx;
  size_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    origin_[d] = Real(domain_min[d]);
    n_nodes_[d] = int(std::ceil((domain_max[d] - domain_min[d]) / dx - 1e-9)) + 1;
    // Padding below node 0 and above the last node, plus one block for the +1 neighbour.
    n_slots_[d] = ((n_nodes_[d] + 2 * kPad) >> kLogBlock) + 2;
    total *= size_t(n_slots_[d]);
  }
  table_.assign(total, -1);
  counts_.assign(total, 0);
  block_slot_.clear();
  binned_ = false;
}

template <int Dim>
IVec<Dim> SparseGrid<Dim>::slot_coord(int slot) const {
  IVec<Dim> b;
  for (int d = 0; d < Dim; ++d) {
    b[d] = slot % n_slots_[d];
    slot /= n_slots_[d];
  }
  return b;
}

template <int Dim>
void SparseGrid<Dim>::bin(const std::vector<const std::vector<Vec<Dim>>*>& groups,
                          std::vector<std::vector<int>>* slots) {
  // Every particle in the home slot it had at the last bin(): the bins and active blocks are
  // what they were (they follow from the slots alone, in particle order); only the node fields
  // are zeroed. A body at rest or moving less than a block does this most steps.
  if (slots && binned_ && bins_.size() == groups.size() && same_slots(*slots)) {
    for (size_t g = 0; g < groups.size(); ++g) bins_[g].particle_slot.swap((*slots)[g]);
    zero_momentum_fields();
    return;
  }
  binned_ = false;
  bins_.resize(groups.size());
  // Reset the previous activation.
  for (int s : block_slot_) table_[s] = -1;
  block_slot_.clear();
  std::vector<int> all_homes;  // home slots of every group
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::vector<Vec<Dim>>& x = *groups[g];
    ParticleBins<Dim>& b = bins_[g];
    const size_t n = x.size();
    // Positions are clamped inside the domain, so only a NaN or infinity (an unstable run)
    // can fall outside the slot table; that is the user's problem to hear about, not an abort.
    std::atomic<bool> non_finite{false};
    if (slots) {
      TEAR_ASSERT((*slots)[g].size() == n);
      b.particle_slot.swap((*slots)[g]);
      if (parallel_any(n, [&](size_t p) { return b.particle_slot[p] < 0; })) non_finite = true;
    } else {
      reserve_large(&b.particle_slot, n);
      b.particle_slot.resize(n);
      parallel_for(n, [&](size_t p) {
        b.particle_slot[p] = home_slot(x[p]);
        if (b.particle_slot[p] < 0) non_finite = true;
      });
    }
    if (non_finite)
      throw std::runtime_error(
          "the simulation became unstable (non-finite particle positions); lower time.cfl or "
          "time.max_dt, or check material stiffness against the time step");

    // Home blocks (with particles) in slot order. Particles are kept sorted by block, so runs
    // of one slot are long: the table is looked at only where the slot changes.
    b.home_blocks.clear();
    std::vector<int> home_slots;
    int previous = -1;
    for (size_t p = 0; p < n; ++p) {
      const int s = b.particle_slot[p];
      if (s == previous) continue;
      previous = s;
      if (table_[s] == -2) continue;
      table_[s] = -2;  // mark seen
      home_slots.push_back(s);
    }
    std::sort(home_slots.begin(), home_slots.end());
    const size_t homes = home_slots.size();
    for (size_t h = 0; h < homes; ++h) counts_[home_slots[h]] = uint32_t(h);  // slot -> home
    // Stable counting sort of the particles by home block, in parallel over chunks of
    // particles: each chunk counts its particles per block, the counts give each (block,
    // chunk) its place, and each chunk fills its places in particle order. The order is the
    // one a serial stable sort gives (ascending index within a block), for any thread count.
    const size_t chunk = std::max<size_t>(16384, n / 64 + 1);
    const size_t chunks = (n + chunk - 1) / chunk;
    std::vector<uint32_t> place(chunks * homes, 0);  // [c][h]: count, then fill cursor
    parallel_for(chunks, [&](size_t c) {
      uint32_t* count = &place[c * homes];
      for (size_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p)
        ++count[counts_[b.particle_slot[p]]];
    });
    uint32_t offset = 0;
    for (size_t h = 0; h < homes; ++h) {
      const uint32_t begin = offset;
      for (size_t c = 0; c < chunks; ++c) {
        const uint32_t k = place[c * homes + h];
        place[c * homes + h] = offset;
        offset += k;
      }
      b.home_blocks.push_back({home_slots[h], begin, offset});
    }
    reserve_large(&b.order, n);
    b.order.resize(n);
    parallel_for(chunks, [&](size_t c) {
      uint32_t* cursor = &place[c * homes];
      for (size_t p = c * chunk; p < std::min(n, (c + 1) * chunk); ++p)
        b.order[cursor[counts_[b.particle_slot[p]]]++] = uint32_t(p);
    });
    for (int s : home_slots) counts_[s] = 0, table_[s] = -1;

    for (auto& c : b.colours) c.clear();
    for (size_t h = 0; h < b.home_blocks.size(); ++h) {
      const IVec<Dim> c = slot_coord(b.home_blocks[h].slot);
      int colour = 0;
      for (int d = 0; d < Dim; ++d) colour |= (c[d] & 1) << d;
      b.colours[colour].push_back(int(h));
    }
    all_homes.insert(all_homes.end(), home_slots.begin(), home_slots.end());
  }

  // Active blocks: every home block and its +1 neighbours, in slot order.
  std::vector<int> active;
  active.reserve(all_homes.size() * kColours);
  for (int s : all_homes) {
    const IVec<Dim> b = slot_coord(s);
    for (int c = 0; c < kColours; ++c) {
      IVec<Dim> nb = b;
      for (int d = 0; d < Dim; ++d) nb[d] += (c >> d) & 1;
      active.push_back(slot_of(nb));
    }
  }
  std::sort(active.begin(), active.end());
  active.erase(std::unique(active.begin(), active.end()), active.end());
  block_slot_ = active;
  for (size_t i = 0; i < active.size(); ++i) table_[active[i]] = int(i);

  const size_t nodes = block_slot_.size() * kNodesPerBlock;
  if (mass.size() < nodes) {
    reserve_large(&mass, nodes), reserve_large(&velocity, nodes);
    reserve_large(&velocity_old, nodes);
    mass.resize(nodes), velocity.resize(nodes), velocity_old.resize(nodes);
  }
  zero_momentum_fields();
  binned_ = true;
}

template <int Dim>
bool SparseGrid<Dim>::same_slots(const std::vector<std::vector<int>>& slots) const {
  for (size_t g = 0; g < slots.size(); ++g) {
    const std::vector<int>& now = slots[g];
    const std::vector<int>& then = bins_[g].particle_slot;
    if (now.size() != then.size() ||
        parallel_any(now.size(), [&](size_t p) { return now[p] != then[p]; }))
      return false;
  }
  return true;
}

template <int Dim>
void SparseGrid<Dim>::zero_momentum_fields() {
  parallel_for(block_slot_.size(), [&](size_t blk) {
    const size_t a = blk * kNodesPerBlock;
    std::fill(mass.begin() + a, mass.begin() + a + kNodesPerBlock, Real(0));
    std::fill(velocity.begin() + a, velocity.begin() + a + kNodesPerBlock, Vec<Dim>::Zero());
    std::fill(velocity_old.begin() + a, velocity_old.begin() + a + kNodesPerBlock,
              Vec<Dim>::Zero());
  });
}

template <int Dim>
void SparseGrid<Dim>::zero_scalar_fields() {
  const size_t nodes = num_active_nodes();
  if (scalar.size() < nodes) scalar.resize(nodes), scalar_weight.resize(nodes);
  parallel_for(block_slot_.size(), [&](size_t blk) {
    const size_t a = blk * kNodesPerBlock;
    std::fill(scalar.begin() + a, scalar.begin() + a + kNodesPerBlock, Real(0));
    std::fill(scalar_weight.begin() + a, scalar_weight.begin() + a + kNodesPerBlock, Real(0));
  });
}

template <int Dim>
void SparseGrid<Dim>::zero_split_fields() {
  const size_t nodes = num_active_nodes();
  if (mass2.size() < nodes)
    mass2.resize(nodes), velocity2.resize(nodes), velocity_old2.resize(nodes),
        crack_normal.resize(nodes);
  parallel_for(block_slot_.size(), [&](size_t blk) {
    const size_t a = blk * kNodesPerBlock, b = a + kNodesPerBlock;
    std::fill(mass2.begin() + a, mass2.begin() + b, Real(0));
    std::fill(velocity2.begin() + a, velocity2.begin() + b, Vec<Dim>::Zero());
    std::fill(velocity_old2.begin() + a, velocity_old2.begin() + b, Vec<Dim>::Zero());
    std::fill(crack_normal.begin() + a, crack_normal.begin() + b, Vec<Dim>::Zero());
  });
}

template <int Dim>
std::vector<std::vector<char>> SparseGrid<Dim>::near_hot_blocks(
    const std::vector<std::vector<char>>& hot) const {
  // Mark the 3^Dim slot neighbourhood of every hot home block (slot coordinates of home
  // blocks are at least 1 and at most n_slots - 2, so the neighbourhood stays in the table).
  std::vector<char> mark(table_.size(), 0);
  int stride[Dim];
  stride[0] = 1;
  for (int d = 1; d < Dim; ++d) stride[d] = stride[d - 1] * n_slots_[d - 1];
  int offsets[Dim == 2 ? 9 : 27], n_off = 0;
  for (int k = 0; k < (Dim == 2 ? 9 : 27); ++k) {
    int o = 0, rest = k;
    for (int d = 0; d < Dim; ++d, rest /= 3) o += (rest % 3 - 1) * stride[d];
    offsets[n_off++] = o;
  }
  for (size_t g = 0; g < bins_.size(); ++g)
    for (size_t h = 0; h < bins_[g].home_blocks.size(); ++h)
      if (hot[g][h])
        for (int o : offsets) mark[size_t(bins_[g].home_blocks[h].slot + o)] = 1;
  std::vector<std::vector<char>> near(bins_.size());
  for (size_t g = 0; g < bins_.size(); ++g) {
    const auto& homes = bins_[g].home_blocks;
    near[g].resize(homes.size());
    for (size_t h = 0; h < homes.size(); ++h) near[g][h] = mark[size_t(homes[h].slot)];
  }
  return near;
}

template <int Dim>
IVec<Dim> SparseGrid<Dim>::node_coord(int node) const {
  const IVec<Dim> b = slot_coord(block_slot_[node / kNodesPerBlock]);
  int local = node % kNodesPerBlock;
  IVec<Dim> g;
  for (int d = 0; d < Dim; ++d) {
    g[d] = (b[d] << kLogBlock) + (local & (kBlock - 1)) - kPad;
    local >>= kLogBlock;
  }
  return g;
}

template <int Dim>
int SparseGrid<Dim>::node_index(const IVec<Dim>& g) const {
  IVec<Dim> b;
  int local = 0;
  for (int d = Dim - 1; d >= 0; --d) {
    const int gp = g[d] + kPad;
    if (gp < 0 || (gp >> kLogBlock) >= n_slots_[d]) return -1;
    b[d] = gp >> kLogBlock;
    local = (local << kLogBlock) | (gp & (kBlock - 1));
  }
  const int blk = table_[slot_of(b)];
  return blk < 0 ? -1 : blk * kNodesPerBlock + local;
}

template <int Dim>
size_t SparseGrid<Dim>::memory_bytes() const {
  size_t bins = 0;
  for (const ParticleBins<Dim>& b : bins_)
    bins += b.order.capacity() * sizeof(uint32_t) + b.particle_slot.capacity() * sizeof(int);
  return table_.size() * (sizeof(int) + sizeof(uint32_t)) +
         mass.capacity() * (sizeof(Real) + 2 * sizeof(Vec<Dim>)) +
         scalar.capacity() * 2 * sizeof(Real) +
         mass2.capacity() * (sizeof(Real) + 3 * sizeof(Vec<Dim>)) + bins;
}

template class SparseGrid<2>;
template class SparseGrid<3>;

}  // namespace tear
