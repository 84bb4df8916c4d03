// mpm/: the phase-field damage update of one step (EQUATIONS.md §1), explicit and implicit.
// The per-particle physics (driving force, structural tensor, degradation) lives in damage/;
// this file does the grid transfers, which need the particles and the sparse grid.
//
// Both solvers integrate the same semi-discrete law on the particles,
//   eta d_p' = < (1 - d_p) D_p - (d_p - l0^2 (L d)_p) >,
// where (L d)_p = sum_i LapN_i(x_p) d_i is the Laplacian of the normalised cubic B-spline
// average d_i = sum_q w_iq d_q / sum_q w_iq (supplement Alg. 4). Explicit: forward Euler
// (paper Eq. 11). Implicit: backward Euler, solved for the particles' damage by sweeps
// (docs/materials.md "Damage solvers"), so that it tends to the explicit result as dt shrinks.
#include "tear/damage/driving_force.h"
#include "tear/math/parallel.h"
#include "tear/mpm/solver.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace tear {

namespace {
// Cubic B-spline: the damage kernel (supplement Alg. 4, 7: "we must use cubic B-spline").
constexpr int kDamageOrder = 3;

// hot[h]: home block h (index into grid.home_blocks()) holds a particle with d > 0.
template <int Dim>
std::vector<char> damaged_blocks(const Particles<Dim>& p, const SparseGrid<Dim>& grid) {
  const auto& order = grid.order();
  const auto& homes = grid.home_blocks();
  std::vector<char> hot(homes.size(), 0);
  tbb::parallel_for(size_t(0), homes.size(), [&](size_t h) {
    for (uint32_t k = homes[h].begin; k < homes[h].end && !hot[h]; ++k)
      hot[h] = p.damage[order[k]] > 0;
  });
  return hot;
}

// The particles' damage to the grid, d_i = sum_p w_ip d_p / sum_p w_ip (cubic B-spline), from
// the particles of the home blocks flagged in `near` (coloured, so without races, in a fixed
// order). Outside those blocks' stencils the field is 0; so is it where no damaged particle
// is near (see SparseGrid::near_hot_blocks).
template <int Dim>
void damage_to_grid(const Particles<Dim>& p, SparseGrid<Dim>* grid,
                    const std::vector<char>& near) {
  SparseGrid<Dim>& g = *grid;
  g.zero_scalar_fields();
  const auto& order = g.order();
  const auto& homes = g.home_blocks();
  for (int c = 0; c < SparseGrid<Dim>::kColours; ++c) {
    const std::vector<int>& blocks = g.colour(c);
    tbb::parallel_for(size_t(0), blocks.size(), [&](size_t b) {
      if (!near[size_t(blocks[b])]) return;
      const auto& h = homes[size_t(blocks[b])];
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t q = order[k];
        const Real d = p.damage[q];
        Stencil<Dim, kDamageOrder>(g, p.x[q]).visit([&](int i, Real w, const Vec<Dim>&) {
          g.scalar[i] += w * d;
          g.scalar_weight[i] += w;
        });
      }
    });
  }
  tbb::parallel_for(size_t(0), g.num_active_nodes(), [&](size_t i) {
    if (g.scalar_weight[i] > 0) g.scalar[i] /= g.scalar_weight[i];
  });
}

// One sweep of a damage update over the damageable particles of the home blocks flagged in
// `visit`: d_p <- rule(p, l0^2 (L d)_p, dt / eta_p), with the Laplacian of the grid field (0
// outside the blocks flagged in `near`). Returns the largest change; marks in `hot` the visited
// blocks that now hold damaged particles.
template <int Dim, class Rule>
Real damage_sweep(Particles<Dim>* particles, const SparseGrid<Dim>& grid,
                  const std::vector<DamageSpec>& specs, Real l0, Real dt,
                  const std::vector<char>& visit, const std::vector<char>& near, Rule&& rule,
                  std::vector<char>* hot) {
  Particles<Dim>& p = *particles;
  const Real l2 = l0 * l0;
  const auto& order = grid.order();
  const auto& homes = grid.home_blocks();
  std::vector<Real> change(homes.size(), 0);
  tbb::parallel_for(size_t(0), homes.size(), [&](size_t b) {
    if (!visit[b]) return;
    Real most = 0;
    bool damaged = false;
    for (uint32_t k = homes[b].begin; k < homes[b].end; ++k) {
      const uint32_t q = order[k];
      const DamageSpec& ds = specs[p.material[q]];
      if (!ds.enabled) continue;
      Real lap = 0;
      if (near[b]) {
        Stencil<Dim, kDamageOrder>(grid, p.x[q]).visit_laplacian(
            [&](int i, Real lap_w) { lap += lap_w * grid.scalar[i]; });
      }
      const Real old = p.damage[q];
      const Real d = rule(q, l2 * lap, dt / Real(ds.eta));
      p.damage[q] = d;
      most = std::max(most, std::abs(d - old));
      damaged = damaged || d > 0;
    }
    change[b] = most;
    if (hot && damaged) (*hot)[b] = 1;
  });
  return *std::max_element(change.begin(), change.end());
}

}  // namespace

template <int Dim>
void MpmSolver<Dim>::damage_step(double dt) {
  sort_particles();
  damage_update(Real(dt));
}

template <int Dim>
void MpmSolver<Dim>::damage_update(Real dt) {
  if (scene_.damage.solver == DamageSolver::None) return;
  // Damage grows only where a driving force is or was (its history never decreases), so
  // without one anywhere nothing can change.
  if (!update_driving_force()) return;
  if (scene_.damage.solver == DamageSolver::Explicit)
    damage_explicit(dt);
  else
    damage_implicit(dt);
}

template <int Dim>
bool MpmSolver<Dim>::update_driving_force() {
  const Real zeta = Real(scene_.damage.zeta);
  piola_.resize(p_.size());
  piola_fresh_ = true;
  std::atomic<bool> any(false);
  tbb::parallel_for(size_t(0), p_.size(), [&](size_t p) {
    const DamageSpec& ds = damage_[p_.material[p]];
    if (!ds.enabled) return;
    const Real alpha[2] = {Real(ds.alpha[0]), Real(ds.alpha[1])};
    const Real excess = particle_phi_excess<Dim>(mats_[p_.material[p]], p_.F[p], p_.fiber[p],
                                                 alpha, Real(ds.sigma_c), &piola_[p]);
    p_.drive[p] = std::max(p_.drive[p], zeta * excess);
    if (p_.drive[p] > 0 || p_.damage[p] > 0) any.store(true, std::memory_order_relaxed);
  });
  return any.load();
}

template <int Dim>
void MpmSolver<Dim>::damage_explicit(Real dt) {
  // Forward Euler (supplement Alg. 3-5): d grows where the undamaged part of the driving force
  // beats the geometric resistance Dc = d - l0^2 Lap d (which also lets a crack widen to its
  // regularised width l0), capped at 1. While nothing nearby is damaged the field and its
  // Laplacian are zero: particles outside the neighbourhood of damaged ones skip the transfer.
  const std::vector<char> near = grid_.near_hot_blocks(damaged_blocks(p_, grid_));
  damage_to_grid(p_, &grid_, near);
  const std::vector<char> all(near.size(), 1);
  damage_sweep(&p_, grid_, damage_, Real(scene_.damage.l0), dt, all, near,
               [&](uint32_t p, Real l2_lap, Real k) {
                 const Real d = p_.damage[p];
                 const Real rate = (1 - d) * p_.drive[p] - (d - l2_lap);
                 return rate > 0 ? std::min(Real(1), d + k * rate) : d;
               },
               nullptr);
}

template <int Dim>
void MpmSolver<Dim>::damage_implicit(Real dt) {
  // Backward Euler of the same law: with k = dt / eta and the bracket active,
  //   (1 + k (1 + D_p)) d_p - k l0^2 (L d)_p = d_p^n + k D_p,
  // and d_p = d_p^n where it is not (damage never heals), capped at 1. That is the fixed point
  // d_p = clamp((d_p^n + k (D_p + l0^2 (L d)_p)) / (1 + k (1 + D_p)), d_p^n, 1), found by
  // sweeps that take the Laplacian of the previous sweep's damage (Jacobi). The first sweep
  // treats the reaction implicitly and the Laplacian explicitly; the sweep's error factor is
  // at most k rho / (1 + k) with rho the spectral radius of l0^2 L (about 0.35 (2 l0 / dx)^2,
  // measured), below 1 for any eta when l0 <= 0.8 dx. Larger l0 with large k relax the
  // sweep by omega = 2 / (2 + k rho / (1 + k)), which keeps the factor below 1.
  const DamageSolverSpec& spec = scene_.damage;
  start_damage_ = p_.damage;
  Real kappa = 0;  // max over materials of k / (1 + k)
  for (const DamageSpec& ds : damage_)
    if (ds.enabled) kappa = std::max(kappa, dt / (Real(ds.eta) + dt));
  const double l0_dx = spec.l0 / scene_.dx;
  const Real rho = Real(kLaplacianRadius * 4 * l0_dx * l0_dx) * kappa;
  const Real omega = rho <= 1 ? Real(1) : Real(2) / (2 + rho);
  auto rule = [&](uint32_t p, Real l2_lap, Real k) {
    const Real d0 = start_damage_[p], D = p_.drive[p];
    const Real target = std::clamp((d0 + k * (D + l2_lap)) / (1 + k * (1 + D)), d0, Real(1));
    return omega == 1 ? target : (1 - omega) * p_.damage[p] + omega * target;
  };
  std::vector<char> hot = damaged_blocks(p_, grid_);
  std::vector<char> near = grid_.near_hot_blocks(hot);
  std::vector<char> visit(near.size(), 1);  // the first sweep: every particle
  int sweeps = 0;
  Real change = 0;
  while (sweeps < spec.max_iterations) {
    damage_to_grid(p_, &grid_, near);
    change = damage_sweep(&p_, grid_, damage_, Real(spec.l0), dt, visit, near, rule, &hot);
    ++sweeps;
    if (change <= spec.tolerance) break;
    // Only particles near damage see a Laplacian that the last sweep changed.
    near = grid_.near_hot_blocks(hot);
    visit = near;
  }
  DamageSolveStats& s = damage_stats_;
  ++s.solves;
  s.iterations += sweeps;
  s.iterations_max = std::max(s.iterations_max, sweeps);
  s.change_max = std::max(s.change_max, double(change));
  s.unconverged += change <= spec.tolerance ? 0 : 1;
}

template <int Dim>
double MpmSolver<Dim>::damage_dt_limit(bool cracking) const {
  // Forward Euler of eta d' = (1 + D) (d* - d) + l0^2 L d (d* = D / (1 + D)) is monotone,
  // never overshooting d* or amplifying a Laplacian mode, when dt (1 + D + |l0^2 L|) <= eta;
  // |l0^2 L| <= l0^2 max_p sum_i |LapN_i(x_p)| <= 4 dim l0^2 / dx^2 (the normalised average
  // does not grow values; the 1-D cubic B-spline's sum_j |N''(x - j)| is at most 4, at
  // nodes). Damage never decreases, so an overshoot would stay: the limit holds it off. Where
  // D > kDriveCap the overshoot is below 1 / (1 + D) < 1 %, so D counts at most kDriveCap.
  if (scene_.damage.solver != DamageSolver::Explicit) return std::numeric_limits<double>::infinity();
  const double l0_dx = scene_.damage.l0 / scene_.dx;
  const double diffusion = 4.0 * Dim * l0_dx * l0_dx;
  // Largest (1 + min(D, cap) + diffusion) / eta over particles that can still crack.
  double worst = 0;
  for (const DamageSpec& ds : damage_)
    if (ds.enabled) worst = std::max(worst, (1 + (cracking ? kDriveCap : 0) + diffusion) / ds.eta);
  if (!cracking) {
    worst = std::max(worst, parallel_max<double>(
                                p_.size(),
                                [&](size_t p) {
                                  const DamageSpec& ds = damage_[p_.material[p]];
                                  if (!ds.enabled || p_.damage[p] >= 1) return 0.0;
                                  const double D = std::min(double(p_.drive[p]), kDriveCap);
                                  return (1 + D + diffusion) / ds.eta;
                                },
                                0.0));
  }
  return worst > 0 ? 1 / worst : std::numeric_limits<double>::infinity();
}

#define TEAR_DAMAGE_INSTANTIATE(D)                                 \
  template void MpmSolver<D>::damage_step(double);                 \
  template void MpmSolver<D>::damage_update(Real);                 \
  template bool MpmSolver<D>::update_driving_force();              \
  template void MpmSolver<D>::damage_explicit(Real);               \
  template void MpmSolver<D>::damage_implicit(Real);               \
  template double MpmSolver<D>::damage_dt_limit(bool) const;
TEAR_DAMAGE_INSTANTIATE(2)
TEAR_DAMAGE_INSTANTIATE(3)
#undef TEAR_DAMAGE_INSTANTIATE

}  // namespace tear
