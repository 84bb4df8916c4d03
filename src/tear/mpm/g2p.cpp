// The G2P phase: particle velocity, affine matrix, position and deformation gradient.
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

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
  // Particles are kept one cell inside the domain.
  Vec<Dim> lo, hi;
  for (int d = 0; d < Dim; ++d) {
    lo[d] = Real(settings.domain_min[d] + settings.dx);
    hi[d] = Real(settings.domain_max[d] - settings.dx);
  }
  for (Particles<Dim>& p : state->groups) {
    parallel_for(p.size(), [&](size_t i) {
      Vec<Dim> v = Vec<Dim>::Zero(), v_old = Vec<Dim>::Zero();
      Mat<Dim> B = Mat<Dim>::Zero();
      Stencil<Dim, kTransferOrder>(grid, p.x[i]).visit([&](int node, Real w, const Vec<Dim>& rel) {
        const Vec<Dim>* vel = &grid.velocity[node];
        const Vec<Dim>* vel_old = &grid.velocity_old[node];
        if constexpr (kSplit) {
          if (second_field(grid, node, p.damage_gradient[i]))
            vel = &grid.velocity2[node], vel_old = &grid.velocity_old2[node];
        }
        const Vec<Dim> wv = w * *vel;
        v += wv;
        for (int c = 0; c < Dim; ++c) B.col(c) += wv * rel[c];  // B += wv (x_i - x_p)^T
        if constexpr (flip) v_old += w * *vel_old;
      });
      const Mat<Dim> C = B * inv_d;  // velocity gradient estimate (APIC B D^-1)
      p.C[i] = C;
      p.F[i] = (Mat<Dim>::Identity() + dt * C) * p.F[i];
      p.v[i] = flip ? Vec<Dim>(ratio * (p.v[i] + v - v_old) + (1 - ratio) * v) : v;
      p.x[i] = (p.x[i] + dt * v).cwiseMax(lo).cwiseMin(hi);
    });
  }
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
