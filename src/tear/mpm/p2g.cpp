// The P2G phase: mass and momentum to the grid, with the stress as an affine momentum term.
#include "tear/damage/driving_force.h"
#include "tear/exec/parallel.h"
#include "tear/materials/registry.h"
#include "tear/mpm/phases.h"
#include "tear/mpm/transfer_window.h"

namespace tear {

template <int Dim>
Mat<Dim> p2g_kirchhoff(const MpmSettings& settings, const Particles<Dim>& p, size_t i, Real scale) {
  const MaterialParams& m = settings.materials[p.material[i]];
  const Mat<Dim>& F = p.F[i];
  // (scale P) F^T as Eigen evaluates scale (P F^T): the scale goes in first.
  auto scaled = [&](const Mat<Dim>& P) -> Mat<Dim> { return scale * (P * F.transpose()); };
  // Without the constitutive phase (no damage), the stress is made here: P2G is its only use.
  if (!has_stress_phase(settings)) {
    if (model_traits(m.model).closed_form_kirchhoff)
      return scale * kirchhoff_stress<Dim>(m, F, p.fiber_of(i));
    return scaled(first_piola<Dim>(m, F, p.fiber_of(i)));
  }
  const DamageParams& dp = settings.material_damage[p.material[i]];
  if (!dp.enabled) return scaled(p.stress[i]);  // g = 1
  // Damageable particles (qr_aniso only: the scene refuses damage on other models): the
  // undegraded stress degraded in closed form, without a second QR, where det F > 0.
  const Real g = degradation(p.damage[i], Real(dp.residual));
  if (p.J[i] > 0)
    return scaled(p.damage[i] == 0 ? p.stress[i] : degrade_qr_stress<Dim>(m, F, p.stress[i], g));
  return scaled(first_piola<Dim>(m, F, p.fiber_of(i), g));
}

namespace {

// P2G with the transfer's choice and crack fields made at compile time (no test per node).
// Home blocks of one colour in parallel; each copies the nodes its particles reach into a
// window, adds its particles there in ascending order and copies the sums back: the same
// additions in the same order as adding into the grid directly.
template <int Dim, bool kApic, bool kFlip, bool kSplit>
void scatter(const MpmSettings& settings, MpmState<Dim>* state, Real dt) {
  SparseGrid<Dim>& grid = state->grid;
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  scatter_home_blocks(*state, [&](size_t g, const typename SparseGrid<Dim>::HomeBlock& h) {
    const Particles<Dim>& p = state->groups[g];
    const uint32_t* order = grid.bins(g).order.data();
    const BlockWindow<Dim, kTransferOrder> window(grid, h, p.x, order);
    using Win = ScatterWindow<Dim, kFlip, kSplit>;
    using Node = typename Win::Node;
    thread_local Win win;
    win.load(grid, window);
    constexpr int kSecond = kSplit ? 1 : 0;
    Node* const mass_momentum[2] = {win.mass_momentum[0].data(), win.mass_momentum[kSecond].data()};
    Node* const momentum_old[2] = {win.momentum_old[0].data(), win.momentum_old[kSecond].data()};
    const Vec<Dim>* const normal = win.normal.data();
    const GroupKind kind = p.kind;
    for (uint32_t k = h.begin; k < h.end; ++k) {
      const uint32_t i = order[k];
      // MLS-MPM: the stress enters as an affine momentum term (Hu et al. 2018, Eq. 29). Mesh
      // vertices carry their elements' in-manifold force (a momentum dt f, not in FLIP's
      // force-free momentum) and shares of their normal stress (codim/elements.h).
      Mat<Dim> stress;
      Real m = p.mass[i];
      if (kind == GroupKind::Volumetric)
        stress = p2g_kirchhoff(settings, p, i, -dt * p.vol0[i] * inv_d);
      else  // mesh vertices (element particles are not binned)
        stress = (-dt * inv_d) * p.stress[i];
      // At a node, w (m, m v + A (x_i - x_p)) in the lanes (m, p), A the stress term plus
      // m C for APIC: m v plus the columns of A times the components of x_i - x_p one by one,
      // as the scalar sums would go; lane 0 adds zeros to m.
      const Vec<Dim> mv = m * p.v[i];
      const Node base_old{m, mv[0], mv[1], Dim == 3 ? mv[Dim - 1] : 0};
      Node base = base_old;
      if (kind == GroupKind::MeshVertices) {
        const Vec<Dim> push = dt * p.force[i];
        base += Node{0, push[0], push[1], Dim == 3 ? push[Dim - 1] : 0};
      }
      Node column[Dim];
      for (int c = 0; c < Dim; ++c) {
        Vec<Dim> a = stress.col(c);
        if constexpr (kApic) a += m * p.C[i].col(c);
        column[c] = Node{0, a[0], a[1], Dim == 3 ? a[Dim - 1] : 0};
      }
      WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit([&](int wn, Real w,
                                                                   const Vec<Dim>& rel) {
        int f = 0;
        if constexpr (kSplit) f = second_field(normal[wn], p.damage_gradient[i]) ? 1 : 0;
        Node sum = base;
        for (int c = 0; c < Dim; ++c) sum += column[c] * rel[c];
        mass_momentum[f][wn] += w * sum;
        if constexpr (kFlip) momentum_old[f][wn] += w * base_old;  // force-free: w m v in lanes 1..
      });
    }
    win.store(&grid, window);
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

template Mat<2> p2g_kirchhoff<2>(const MpmSettings&, const Particles<2>&, size_t, Real);
template Mat<3> p2g_kirchhoff<3>(const MpmSettings&, const Particles<3>&, size_t, Real);
template void p2g<2>(const MpmSettings&, MpmState<2>*, Real);
template void p2g<3>(const MpmSettings&, MpmState<3>*, Real);

}  // namespace tear
