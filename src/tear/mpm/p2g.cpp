// The P2G phase: mass and momentum to the grid, with the stress as an affine momentum term.
#include "tear/damage/driving_force.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

namespace tear {

template <int Dim>
Mat<Dim> p2g_stress(const MpmSettings& settings, const Particles<Dim>& p, size_t i) {
  const DamageParams& dp = settings.material_damage[p.material[i]];
  if (!dp.enabled) return p.stress[i];  // g = 1
  // Damageable particles (qr_aniso only: the scene refuses damage on other models): the
  // undegraded stress degraded in closed form, without a second QR, where det F > 0.
  const MaterialParams& m = settings.materials[p.material[i]];
  if (p.J[i] > 0) {
    if (p.damage[i] == 0) return p.stress[i];
    return degrade_qr_stress<Dim>(m, p.F[i], p.stress[i],
                                  degradation(p.damage[i], Real(dp.residual)));
  }
  return first_piola<Dim>(m, p.F[i], p.fiber[i], degradation(p.damage[i], Real(dp.residual)));
}

namespace {

// P2G with the transfer's choice and crack fields made at compile time (no test per node).
template <int Dim, bool kApic, bool kFlip, bool kSplit>
void scatter(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  SparseGrid<Dim>& grid = state->grid;
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  scatter_particles(*state, [&](size_t g, uint32_t i) {
    const Particles<Dim>& p = state->groups[g];
    const Mat<Dim> P = p2g_stress(settings, p, i);
    // MLS-MPM: the stress enters as an affine momentum term (Hu et al. 2018, Eq. 29).
    Mat<Dim> affine = (-dt * p.vol0[i] * inv_d) * (P * p.F[i].transpose());
    const Real m = p.mass[i];
    if constexpr (kApic) affine += m * p.C[i];
    const Vec<Dim> mv = m * p.v[i];
    Stencil<Dim, kTransferOrder>(grid, p.x[i]).visit([&](int node, Real w, const Vec<Dim>& rel) {
      Real* mass = &grid.mass[node];
      Real* momentum = grid.velocity[node].data();
      Vec<Dim>* momentum_old = &grid.velocity_old[node];
      if constexpr (kSplit) {
        if (second_field(grid, node, p.damage_gradient[i])) {
          mass = &grid.mass2[node];
          momentum = grid.velocity2[node].data();
          momentum_old = &grid.velocity_old2[node];
        }
      }
      *mass += w * m;
      // mv + affine (x_i - x_p), row by row in scalars: Eigen's temporaries here cost
      // store-forwarding stalls.
      for (int a = 0; a < Dim; ++a) {
        Real dv = mv[a];
        for (int c = 0; c < Dim; ++c) dv += affine(a, c) * rel[c];
        momentum[a] += w * dv;
      }
      if constexpr (kFlip) *momentum_old += w * mv;  // force-free momentum
    });
  });
}

template <int Dim, bool kSplit>
void scatter_split(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  switch (settings.transfer) {
    case Transfer::Apic: return scatter<Dim, true, false, kSplit>(settings, state, dt);
    case Transfer::Pic: return scatter<Dim, false, false, kSplit>(settings, state, dt);
    case Transfer::Flip: return scatter<Dim, false, true, kSplit>(settings, state, dt);
  }
}

}  // namespace

template <int Dim>
void p2g(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  if (state->grid.split())
    scatter_split<Dim, true>(settings, state, dt);
  else
    scatter_split<Dim, false>(settings, state, dt);
}

template Mat<2> p2g_stress<2>(const MpmSettings&, const Particles<2>&, size_t);
template Mat<3> p2g_stress<3>(const MpmSettings&, const Particles<3>&, size_t);
template void p2g<2>(const MpmSettings&, MpmState<2>*, Real);
template void p2g<3>(const MpmSettings&, MpmState<3>*, Real);

}  // namespace tear
