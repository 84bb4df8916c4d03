// The G2P phase: particle velocity, affine matrix, position and deformation gradient.
#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"
#include "tear/mpm/transfer_window.h"

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
  // The next sort's home slots, made while the new positions are at hand.
  state->home_slots.resize(state->groups.size());
  // Home blocks in parallel; each copies the nodes its particles reach into a window.
  for (size_t g = 0; g < state->groups.size(); ++g) {
    Particles<Dim>& p = state->groups[g];
    const ParticleBins<Dim>& bins = grid.bins(g);
    std::vector<int>& slots = state->home_slots[g];
    reserve_large(&slots, p.size());
    slots.resize(p.size());
    parallel_for(bins.home_blocks.size(), [&](size_t b) {
      const typename SparseGrid<Dim>::HomeBlock& h = bins.home_blocks[b];
      const BlockWindow<Dim, kTransferOrder> window(grid, h, p.x, bins.order.data());
      thread_local TransferWindow<Dim, kFlip, kSplit> win;
      win.template load<false>(grid, window);
      constexpr int kSecond = kSplit ? 1 : 0;
      const Vec<Dim>* const velocity[2] = {win.field[0].v.data(), win.field[kSecond].v.data()};
      const Vec<Dim>* const velocity_old[2] = {win.field[0].v_old.data(),
                                               win.field[kSecond].v_old.data()};
      const Vec<Dim>* const normal = win.normal.data();
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t i = bins.order[k];
        Vec<Dim> v = Vec<Dim>::Zero(), v_old = Vec<Dim>::Zero();
        Mat<Dim> B = Mat<Dim>::Zero();
        WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit([&](int wn, Real w,
                                                                     const Vec<Dim>& rel) {
          int f = 0;
          if constexpr (kSplit) f = second_field(normal[wn], p.damage_gradient[i]) ? 1 : 0;
          const Vec<Dim> wv = w * velocity[f][wn];
          v += wv;
          for (int c = 0; c < Dim; ++c) B.col(c) += wv * rel[c];  // B += wv (x_i - x_p)^T
          if constexpr (flip) v_old += w * velocity_old[f][wn];
        });
        // C = B D^-1 (the APIC velocity gradient estimate), F <- (I + dt C) F, column by
        // column: B's columns are stored in pieces (two rows packed, one alone), and reading
        // the matrix whole at other offsets stalls on store forwarding (a fifth of G2P).
        Mat<Dim>& C = p.C[i];
        Mat<Dim> G;
        for (int c = 0; c < Dim; ++c) {
          C.col(c) = B.col(c) * inv_d;
          G.col(c) = Vec<Dim>::Unit(c) + dt * C.col(c);
        }
        p.F[i] = G * p.F[i];
        p.v[i] = flip ? Vec<Dim>(ratio * (p.v[i] + v - v_old) + (1 - ratio) * v) : v;
        p.x[i] = (p.x[i] + dt * v).cwiseMax(kept.lo).cwiseMin(kept.hi);
        slots[i] = grid.home_slot(p.x[i]);
      }
    });
  }
  state->home_slots_step = state->steps + 1;
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
