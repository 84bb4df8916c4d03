// The G2P phase: particle velocity, affine matrix, position and deformation gradient.
#include "tear/codim/elements.h"
#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"
#include "tear/mpm/transfer_window.h"

#include <algorithm>
#include <cmath>

namespace tear {

namespace {

// G2P with the transfer's choice and crack fields made at compile time (no test per node).
template <int Dim, bool kFlip, bool kSplit>
void gather(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  constexpr bool flip = kFlip;
  const SparseGrid<Dim>& grid = state->grid;
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  const Real ratio =
      Real(settings.flip_relaxation_time > 0 ? std::exp(-double(dt) / settings.flip_relaxation_time)
                                             : settings.flip_ratio);
  const KeptBox<Dim> kept(settings);
  // The next sort's home slots and the figures of MpmState::Moved, made while the new
  // positions and velocities are at hand.
  state->home_slots.resize(state->groups.size());
  typename MpmState<Dim>::Moved moved;
  std::vector<typename MpmState<Dim>::Moved> block_moved;
  // Home blocks in parallel; each copies the nodes its particles reach into a window.
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    const GroupKind kind = p.kind;
    const ParticleBins<Dim>& bins = grid.bins(g);
    std::vector<int>& slots = state->home_slots[g];
    const size_t binned = bins.particle_slot.size();  // 0 for element particles
    reserve_large(&slots, binned);
    slots.resize(binned);
    block_moved.assign(bins.home_blocks.size(), moved);
    parallel_for(bins.home_blocks.size(), [&](size_t b) {
      const typename SparseGrid<Dim>::HomeBlock& h = bins.home_blocks[b];
      const BlockWindow<Dim, kTransferOrder> window(grid, h, p.x, bins.order.data());
      using Win = GatherWindow<Dim, kFlip, kSplit>;
      using Node = typename Win::Node;
      thread_local Win win;
      win.load(grid, window);
      constexpr int kSecond = kSplit ? 1 : 0;
      const Node* const velocity[2] = {win.velocity[0].data(), win.velocity[kSecond].data()};
      const Node* const velocity_old[2] = {win.velocity_old[0].data(),
                                           win.velocity_old[kSecond].data()};
      const Vec<Dim>* const normal = win.normal.data();
      typename MpmState<Dim>::Moved& m = block_moved[b];
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t i = bins.order[k];
        // In lanes: v, the force-free v and the columns of B = sum w v_i (x_i - x_p)^T.
        Node v{}, v_old{}, B[Dim];
        for (int c = 0; c < Dim; ++c) B[c] = Node{};
        WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit([&](int wn, Real w,
                                                                     const Vec<Dim>& rel) {
          int f = 0;
          if constexpr (kSplit) f = second_field(normal[wn], p.damage_gradient[i]) ? 1 : 0;
          const Node wv = w * velocity[f][wn];
          v += wv;
          for (int c = 0; c < Dim; ++c) B[c] += wv * rel[c];
          if constexpr (flip) v_old += w * velocity_old[f][wn];
        });
        // C = B D^-1 (the APIC velocity gradient estimate), F <- (I + dt C) F, in lanes
        // (column c of G = I + dt C in lanes; column b of G F sums G's columns times F(c, b)
        // in order, as Eigen's product does); scalars go out, no vector is read back.
        Mat<Dim>& C = p.C[i];
        Node G[Dim];
        for (int c = 0; c < Dim; ++c) {
          const Node Cc = B[c] * inv_d;
          Node unit{};
          unit[c] = 1;
          G[c] = unit + dt * Cc;
          for (int a = 0; a < Dim; ++a) C(a, c) = Cc[a];
        }
        // Mesh vertices have no F (element particles are not binned: update_element_geometry).
        if (kind == GroupKind::Volumetric) {
          const Mat<Dim> F = p.F[i];
          for (int b = 0; b < Dim; ++b) {
            Node col = G[0] * F(0, b);
            for (int c = 1; c < Dim; ++c) col += G[c] * F(c, b);
            for (int a = 0; a < Dim; ++a) p.F[i](a, b) = col[a];
          }
        }
        Vec<Dim> vg, vg_old;
        for (int a = 0; a < Dim; ++a) vg[a] = v[a], vg_old[a] = v_old[a];
        p.v[i] = flip ? Vec<Dim>(ratio * (p.v[i] + vg - vg_old) + (1 - ratio) * vg) : vg;
        p.x[i] = (p.x[i] + dt * vg).cwiseMax(kept.lo).cwiseMin(kept.hi);
        slots[i] = grid.home_slot(p.x[i]);
        m.speed2 = std::max(m.speed2, kept.speed2_or_fault(p.x[i], p.v[i]));
        m.min_mass = std::min(m.min_mass, p.mass[i]);
      }
    });
    // Maxima and minima: the same for any order, so for any thread count.
    for (const typename MpmState<Dim>::Moved& m : block_moved) {
      moved.speed2 = std::max(moved.speed2, m.speed2);
      moved.min_mass = std::min(moved.min_mass, m.min_mass);
    }
  }
  // Element particles at their vertices' new places (vertex groups were all moved above).
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    if (element_dimension(p.kind) == 0) continue;
    update_element_geometry(state->groups[size_t(p.vertex_group)], dt, &p);
    moved.speed2 = std::max(
        moved.speed2, parallel_max<Real>(
                          p.size(), [&](size_t i) { return kept.speed2_or_fault(p.x[i], p.v[i]); },
                          Real(0)));
  }
  state->home_slots_step = state->steps + 1;
  state->moved = moved;
  state->moved_step = state->steps + 1;
}

}  // namespace

template <int Dim>
void g2p(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  const bool flip = settings.transfer == Transfer::Flip, split = state->grid.split();
  if (flip && split) return gather<Dim, true, true>(settings, state, dt);
  if (flip) return gather<Dim, true, false>(settings, state, dt);
  if (split) return gather<Dim, false, true>(settings, state, dt);
  gather<Dim, false, false>(settings, state, dt);
}

template void g2p<2>(const MpmSettings&, MpmState<2>*, Real);
template void g2p<3>(const MpmSettings&, MpmState<3>*, Real);

}  // namespace tear
