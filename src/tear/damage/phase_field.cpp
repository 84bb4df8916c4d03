#include "tear/damage/phase_field.h"

#include "tear/damage/driving_force.h"
#include "tear/exec/parallel.h"
#include "tear/grid/block_window.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace tear {

namespace {

// Cubic B-spline: the damage kernel (supplement Alg. 4, 7: "we must use cubic B-spline").
constexpr int kDamageOrder = 3;
template <int Dim>
using Window = BlockWindow<Dim, kDamageOrder>;

template <int Dim>
using Groups = std::vector<Particles<Dim>>;
// Per group, per home block (index into the group's bins().home_blocks): a flag.
using BlockFlags = std::vector<std::vector<char>>;

// hot[g][h]: home block h of group g holds a particle with d > 0.
template <int Dim>
BlockFlags damaged_blocks(const Groups<Dim>& groups, const SparseGrid<Dim>& grid) {
  BlockFlags hot(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    const Particles<Dim>& p = groups[g];
    const ParticleBins<Dim>& bins = grid.bins(g);
    hot[g].assign(bins.home_blocks.size(), 0);
    parallel_for(bins.home_blocks.size(), [&](size_t h) {
      for (uint32_t k = bins.home_blocks[h].begin; k < bins.home_blocks[h].end && !hot[g][h]; ++k)
        hot[g][h] = p.damage[bins.order[k]] > 0;
    });
  }
  return hot;
}

// The particles' damage to the grid, d_i = sum_p w_ip d_p / sum_p w_ip (B-spline of order
// `Order`: cubic for the damage update, kDamageOrder), from
// the particles of the home blocks flagged in `near` (coloured, so without races, in a fixed
// order). Outside those blocks' stencils the field is 0; so is it where no damaged particle
// is near (see SparseGrid::near_hot_blocks).
template <int Dim, int Order = kDamageOrder>
void damage_to_grid(const Groups<Dim>& groups, SparseGrid<Dim>* grid, const BlockFlags& near,
                    Domain& domain) {
  SparseGrid<Dim>& g = *grid;
  g.zero_scalar_fields();
  for_each_colour(
      SparseGrid<Dim>::kColours, groups.size(),
      [&](size_t gr, int c) -> const std::vector<int>& { return g.bins(gr).colours[c]; },
      [&](size_t gr, int b) {
        if (!near[gr][size_t(b)]) return;
        const Particles<Dim>& p = groups[gr];
        const ParticleBins<Dim>& bins = g.bins(gr);
        const auto& h = bins.home_blocks[size_t(b)];
        // In a window of the nodes the block's particles reach (grid/block_window.h): the
        // same additions in the same order as into the grid.
        const BlockWindow<Dim, Order> window(g, h, p.x, bins.order.data());
        constexpr size_t kSize = BlockWindow<Dim, Order>::kSize;
        thread_local std::vector<Real> value(kSize), weight(kSize);
        window.load(g.scalar, value.data());
        window.load(g.scalar_weight, weight.data());
        Real* const sum = value.data();
        Real* const sum_w = weight.data();
        for (uint32_t k = h.begin; k < h.end; ++k) {
          const uint32_t q = bins.order[k];
          const Real d = p.damage[q];
          WindowStencil<Dim, Order>(window, p.x[q]).visit(
              [&](int i, Real w, const Vec<Dim>&) {
                sum[i] += w * d;
                sum_w[i] += w;
              });
        }
        window.store(sum, &g.scalar);
        window.store(sum_w, &g.scalar_weight);
      });
  const size_t n = g.num_active_nodes();
  domain.sum_halos({node_field(g.scalar.data(), n, 1), node_field(g.scalar_weight.data(), n, 1)});
  parallel_for(n, [&](size_t i) {
    if (g.scalar_weight[i] > 0) g.scalar[i] /= g.scalar_weight[i];
  });
  domain.copy_halos({node_field(g.scalar.data(), n, 1)});
}

// One sweep of a damage update over the damageable particles of the home blocks flagged in
// `visit`: d_p <- rule(g, p, l0^2 (L d)_p, dt / eta_p), with the Laplacian of the grid field (0
// outside the blocks flagged in `near`), kept in Particles::damage_laplacian where a run writes
// it to its frames. Returns the largest change; marks in `hot` the visited blocks that now hold
// damaged particles.
template <int Dim, class Rule>
Real damage_sweep(Groups<Dim>* groups, const SparseGrid<Dim>& grid,
                  const std::vector<DamageParams>& params, Real l0, Real dt,
                  const BlockFlags& visit, const BlockFlags& near, Rule&& rule, BlockFlags* hot) {
  const Real l2 = l0 * l0;
  Real most = 0;
  for (size_t g = 0; g < groups->size(); ++g) {
    Particles<Dim>& p = (*groups)[g];
    const ParticleBins<Dim>& bins = grid.bins(g);
    std::vector<Real> change(bins.home_blocks.size(), 0);
    Real* const lap_out = p.enabled("damage_laplacian") ? p.damage_laplacian.data() : nullptr;
    parallel_for(bins.home_blocks.size(), [&](size_t b) {
      if (!visit[g][b]) return;
      Real block_most = 0;
      bool damaged = false;
      const auto& h = bins.home_blocks[b];
      // The grid field near the block in a window (grid/block_window.h), where it is not 0.
      std::optional<Window<Dim>> window;
      thread_local std::vector<Real> value(Window<Dim>::kSize);
      if (near[g][b]) {
        window.emplace(grid, h, p.x, bins.order.data());
        window->load(grid.scalar, value.data());
      }
      const Real* const field = value.data();
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t q = bins.order[k];
        const DamageParams& dp = params[p.material[q]];
        if (!dp.enabled) continue;
        Real lap = 0;  // (L d)_p, or M_p : grad grad d with an anisotropic crack surface
        if (window && dp.anisotropic_surface()) {
          const Mat<Dim> M = crack_surface_tensor<Dim>(p.F[q], p.fiber_of(q), dp.surface);
          WindowStencil<Dim, kDamageOrder, true>(*window, p.x[q])
              .visit_second(M, [&](int i, Real w) { lap += w * field[i]; });
        } else if (window) {
          WindowStencil<Dim, kDamageOrder>(*window, p.x[q]).visit_laplacian(
              [&](int i, Real lap_w) { lap += lap_w * field[i]; });
        }
        if (lap_out) lap_out[q] = lap;
        const Real old = p.damage[q];
        const Real d = rule(g, q, l2 * lap, dt / Real(dp.eta));
        p.damage[q] = d;
        block_most = std::max(block_most, std::abs(d - old));
        damaged = damaged || d > 0;
      }
      change[b] = block_most;
      if (hot && damaged) (*hot)[g][b] = 1;
    });
    for (Real c : change) most = std::max(most, c);
  }
  return most;
}

}  // namespace

template <int Dim>
void update_damage(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                   const DamageSettings& settings, const std::vector<DamageParams>& params,
                   double dt, DamageSolveStats* stats, Domain& domain) {
  if (settings.solver == DamageSolver::None) return;
  // Damage grows only where a driving force is or was (its history never decreases), so
  // without one anywhere nothing can change.
  if (!update_driving_force(groups, params, settings.zeta)) return;
  if (settings.solver == DamageSolver::Explicit)
    damage_explicit(groups, grid, params, Real(settings.l0), Real(dt), domain);
  else
    damage_implicit(groups, grid, settings, params, Real(dt), stats, domain);
}

template <int Dim>
bool update_driving_force(std::vector<Particles<Dim>>* groups,
                          const std::vector<DamageParams>& params, double zeta_in) {
  const Real zeta = Real(zeta_in);
  bool any = false;
  for (Particles<Dim>& p : *groups) {
    any = parallel_any(p.size(),
                       [&](size_t i) {
                         const DamageParams& dp = params[p.material[i]];
                         if (!dp.enabled) return false;
                         const Real alpha[2] = {Real(dp.alpha[0]), Real(dp.alpha[1])};
                         const Real excess = phi_excess<Dim>(p.stress[i], p.J[i], p.F[i],
                                                             p.fiber_of(i), alpha, Real(dp.sigma_c));
                         p.drive[i] = std::max(p.drive[i], zeta * excess);
                         return p.drive[i] > 0 || p.damage[i] > 0;
                       }) ||
          any;
  }
  return any;
}

template <int Order, int Dim>
BlockFlags damage_on_grid(const std::vector<Particles<Dim>>& groups, SparseGrid<Dim>* grid,
                          Domain& domain) {
  static_assert(Order == 2 || Order == 3, "near_hot_blocks' reach is the cubic kernel's");
  BlockFlags near = grid->near_hot_blocks(damaged_blocks(groups, *grid));
  damage_to_grid<Dim, Order>(groups, grid, near, domain);
  return near;
}

template <int Dim>
void damage_explicit(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                     const std::vector<DamageParams>& params, Real l0, Real dt, Domain& domain) {
  // Forward Euler (supplement Alg. 3-5): d grows where the undamaged part of the driving force
  // beats the geometric resistance Dc = d - l0^2 Lap d (which also lets a crack widen to its
  // regularised width l0), capped at 1. While nothing nearby is damaged the field and its
  // Laplacian are zero: particles outside the neighbourhood of damaged ones skip the transfer.
  const BlockFlags near = damage_on_grid<kDamageOrder>(*groups, grid, domain);
  BlockFlags all = near;
  for (auto& flags : all) std::fill(flags.begin(), flags.end(), 1);
  damage_sweep(
      groups, *grid, params, l0, dt, all, near,
      [&](size_t g, uint32_t q, Real l2_lap, Real k) {
        const Particles<Dim>& p = (*groups)[g];
        const Real d = p.damage[q];
        const Real rate = (1 - d) * p.drive[q] - (d - l2_lap);
        return rate > 0 ? std::min(Real(1), d + k * rate) : d;
      },
      nullptr);
}

template <int Dim>
void damage_implicit(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                     const DamageSettings& settings, const std::vector<DamageParams>& params,
                     Real dt, DamageSolveStats* stats, Domain& domain) {
  // Backward Euler of the same law: with k = dt / eta and the bracket active,
  //   (1 + k (1 + D_p)) d_p - k l0^2 (L d)_p = d_p^n + k D_p,
  // and d_p = d_p^n where it is not (damage never heals), capped at 1. That is the fixed point
  // d_p = clamp((d_p^n + k (D_p + l0^2 (L d)_p)) / (1 + k (1 + D_p)), d_p^n, 1), found by
  // sweeps that take the Laplacian of the previous sweep's damage (Jacobi). The first sweep
  // treats the reaction implicitly and the Laplacian explicitly; the sweep's error factor is
  // at most k rho / (1 + k) with rho the spectral radius of l0^2 L (about 0.35 (2 l0 / dx)^2,
  // measured), below 1 for any eta when l0 <= 0.8 dx. Larger l0 with large k relax the
  // sweep by omega = 2 / (2 + k rho / (1 + k)), which keeps the factor below 1.
  std::vector<std::vector<Real>> start(groups->size());  // d^n of the step
  for (size_t g = 0; g < groups->size(); ++g) start[g] = (*groups)[g].damage;
  Real kappa = 0;  // max over materials of k / (1 + k), times the surface term's factor
  for (const DamageParams& dp : params)
    if (dp.enabled) kappa = std::max(kappa, Real(dp.surface_factor()) * dt / (Real(dp.eta) + dt));
  const double l0_dx = settings.l0 / grid->dx();
  const Real rho = Real(kLaplacianRadius * 4 * l0_dx * l0_dx) * kappa;
  const Real omega = rho <= 1 ? Real(1) : Real(2) / (2 + rho);
  auto rule = [&](size_t g, uint32_t q, Real l2_lap, Real k) {
    const Particles<Dim>& p = (*groups)[g];
    const Real d0 = start[g][q], D = p.drive[q];
    const Real target = std::clamp((d0 + k * (D + l2_lap)) / (1 + k * (1 + D)), d0, Real(1));
    return omega == 1 ? target : (1 - omega) * p.damage[q] + omega * target;
  };
  BlockFlags hot = damaged_blocks(*groups, *grid);
  BlockFlags near = grid->near_hot_blocks(hot);
  BlockFlags visit = near;  // the first sweep: every particle
  for (auto& flags : visit) std::fill(flags.begin(), flags.end(), 1);
  int sweeps = 0;
  Real change = 0;
  while (sweeps < settings.max_iterations) {
    damage_to_grid(*groups, grid, near, domain);
    change = Real(domain.max(
        damage_sweep(groups, *grid, params, Real(settings.l0), dt, visit, near, rule, &hot)));
    ++sweeps;
    if (change <= settings.tolerance) break;
    // Only particles near damage see a Laplacian that the last sweep changed.
    near = grid->near_hot_blocks(hot);
    visit = near;
  }
  DamageSolveStats& s = *stats;
  ++s.solves;
  s.iterations += sweeps;
  s.iterations_max = std::max(s.iterations_max, sweeps);
  s.change_max = std::max(s.change_max, double(change));
  s.unconverged += change <= settings.tolerance ? 0 : 1;
}

template <int Dim>
double damage_dt_limit(const std::vector<Particles<Dim>>& groups, const DamageSettings& settings,
                       const std::vector<DamageParams>& params, double dx, bool cracking) {
  // Forward Euler of eta d' = (1 + D) (d* - d) + l0^2 L d (d* = D / (1 + D)) is monotone,
  // never overshooting d* or amplifying a Laplacian mode, when dt (1 + D + |l0^2 L|) <= eta;
  // |l0^2 L| <= l0^2 max_p sum_i |LapN_i(x_p)| <= 4 dim l0^2 / dx^2 (the normalised average
  // does not grow values; the 1-D cubic B-spline's sum_j |N''(x - j)| is at most 4, at
  // nodes). Damage never decreases, so an overshoot would stay: the limit holds it off. Where
  // D > kDriveCap the overshoot is below 1 / (1 + D) < 1 %, so D counts at most kDriveCap.
  // An anisotropic surface term M : grad grad d, M = I + sum_k beta_k w_k w_k^T, has the bound
  // times 1 + sum_k |beta_k|: for a unit w, dx^2 sum_i |w^T H_i w| <= 4 sum_a w_a^2 + (3/2)^2
  // sum_(a != b) |w_a w_b| <= 4 + 2.25 (dim - 1) < 4 dim (the cubic's sum_j |N'| is at most
  // 3/2, midway between nodes).
  if (settings.solver != DamageSolver::Explicit) return std::numeric_limits<double>::infinity();
  const double l0_dx = settings.l0 / dx;
  const double diffusion = 4.0 * Dim * l0_dx * l0_dx;
  // Largest (1 + min(D, cap) + diffusion) / eta over particles that can still crack.
  double worst = 0;
  for (const DamageParams& dp : params)
    if (dp.enabled)
      worst = std::max(worst,
                       (1 + (cracking ? kDriveCap : 0) + diffusion * dp.surface_factor()) / dp.eta);
  if (!cracking) {
    for (const Particles<Dim>& p : groups)
      worst = std::max(worst, parallel_max<double>(
                                  p.size(),
                                  [&](size_t i) {
                                    const DamageParams& dp = params[p.material[i]];
                                    if (!dp.enabled || p.damage[i] >= 1) return 0.0;
                                    const double D = std::min(double(p.drive[i]), kDriveCap);
                                    return (1 + D + diffusion * dp.surface_factor()) / dp.eta;
                                  },
                                  0.0));
  }
  return worst > 0 ? 1 / worst : std::numeric_limits<double>::infinity();
}

#define TEAR_DAMAGE_INSTANTIATE(D)                                                                \
  template void update_damage<D>(std::vector<Particles<D>>*, SparseGrid<D>*,                      \
                                 const DamageSettings&, const std::vector<DamageParams>&, double, \
                                 DamageSolveStats*, Domain&);                                     \
  template BlockFlags damage_on_grid<2, D>(const std::vector<Particles<D>>&, SparseGrid<D>*,     \
                                           Domain&);                                             \
  template BlockFlags damage_on_grid<3, D>(const std::vector<Particles<D>>&, SparseGrid<D>*,     \
                                           Domain&);                                             \
  template bool update_driving_force<D>(std::vector<Particles<D>>*,                               \
                                        const std::vector<DamageParams>&, double);                \
  template void damage_explicit<D>(std::vector<Particles<D>>*, SparseGrid<D>*,                    \
                                   const std::vector<DamageParams>&, Real, Real, Domain&);        \
  template void damage_implicit<D>(std::vector<Particles<D>>*, SparseGrid<D>*,                    \
                                   const DamageSettings&, const std::vector<DamageParams>&, Real, \
                                   DamageSolveStats*, Domain&);                                   \
  template double damage_dt_limit<D>(const std::vector<Particles<D>>&, const DamageSettings&,     \
                                     const std::vector<DamageParams>&, double, bool);
TEAR_DAMAGE_INSTANTIATE(2)
TEAR_DAMAGE_INSTANTIATE(3)
#undef TEAR_DAMAGE_INSTANTIATE

}  // namespace tear
