// mpm/: the phase-field damage update of one step (EQUATIONS.md §1), explicit and implicit.
// The per-particle physics (driving force, structural tensor, degradation) lives in damage/;
// this file does the grid transfers, which need the particles and the sparse grid.
#include "tear/damage/driving_force.h"
#include "tear/math/parallel.h"
#include "tear/mpm/solver.h"
#include "tear/solvers/pcg.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace tear {

namespace {
// Cubic B-spline: the damage kernel (supplement Alg. 4, 7: "we must use cubic B-spline").
constexpr int kDamageOrder = 3;
// MLS-MPM inverse inertia M_p^-1 = 3 / dx^2 of the cubic B-spline (Hu et al. 2018).
constexpr double kCubicInvD = 3.0;
// Smallest J used for the current particle volume V = J V0 in the implicit system (an
// inverted particle still needs a positive weight).
constexpr Real kMinJ = Real(1e-3);
}  // namespace

template <int Dim>
void MpmSolver<Dim>::damage_step(double dt) {
  sort_particles();
  damage_update(Real(dt));
}

template <int Dim>
void MpmSolver<Dim>::damage_update(Real dt) {
  if (scene_.damage.solver == DamageSolver::None) return;
  update_driving_force();
  if (scene_.damage.solver == DamageSolver::Explicit)
    damage_explicit(dt);
  else
    damage_implicit(dt);
}

template <int Dim>
void MpmSolver<Dim>::update_driving_force() {
  const Real zeta = Real(scene_.damage.zeta);
  piola_.resize(p_.size());
  piola_fresh_ = true;
  tbb::parallel_for(size_t(0), p_.size(), [&](size_t p) {
    const DamageSpec& ds = damage_[p_.material[p]];
    if (!ds.enabled) return;
    const Real alpha[2] = {Real(ds.alpha[0]), Real(ds.alpha[1])};
    const Real excess = particle_phi_excess<Dim>(mats_[p_.material[p]], p_.F[p], p_.fiber[p],
                                                 alpha, Real(ds.sigma_c), &piola_[p]);
    p_.drive[p] = std::max(p_.drive[p], zeta * excess);
  });
}

template <int Dim>
std::vector<char> MpmSolver<Dim>::active_damage_blocks(bool with_drive) const {
  const auto& order = grid_.order();
  const auto& homes = grid_.home_blocks();
  std::vector<char> hot(homes.size(), 0);
  tbb::parallel_for(size_t(0), homes.size(), [&](size_t h) {
    for (uint32_t k = homes[h].begin; k < homes[h].end && !hot[h]; ++k) {
      const uint32_t p = order[k];
      hot[h] = p_.damage[p] > 0 || (with_drive && p_.drive[p] > 0);
    }
  });
  return grid_.near_hot_blocks(hot);
}

// Visits the particles of the home blocks flagged in `active` (all when empty): coloured, so
// that fn may scatter to its particles' cubic stencils without races, in a fixed order.
template <int Dim, class Fn>
static void for_active_particles_coloured(const SparseGrid<Dim>& grid,
                                          const std::vector<char>& active, Fn&& fn) {
  const auto& order = grid.order();
  const auto& homes = grid.home_blocks();
  for (int c = 0; c < SparseGrid<Dim>::kColours; ++c) {
    const std::vector<int>& blocks = grid.colour(c);
    tbb::parallel_for(size_t(0), blocks.size(), [&](size_t b) {
      if (!active[size_t(blocks[b])]) return;
      const auto& h = homes[size_t(blocks[b])];
      for (uint32_t k = h.begin; k < h.end; ++k) fn(order[k]);
    });
  }
}

// The same without colouring (gathers only).
template <int Dim, class Fn>
static void for_active_particles(const SparseGrid<Dim>& grid, const std::vector<char>& active,
                                 Fn&& fn) {
  const auto& order = grid.order();
  const auto& homes = grid.home_blocks();
  tbb::parallel_for(size_t(0), homes.size(), [&](size_t b) {
    if (!active[b]) return;
    for (uint32_t k = homes[b].begin; k < homes[b].end; ++k) fn(order[k]);
  });
}

template <int Dim>
void MpmSolver<Dim>::damage_explicit(Real dt) {
  const Real l0 = Real(scene_.damage.l0);
  // While nothing nearby is damaged the field and its Laplacian are zero: particles outside
  // the neighbourhood of damaged ones skip the transfer (exactly: see near_hot_blocks).
  const std::vector<char> active = active_damage_blocks(false);
  // Damage to the grid (cubic B-spline, normalised).
  grid_.zero_scalar_fields();
  for_active_particles_coloured(grid_, active, [&](uint32_t p) {
    const Real d = p_.damage[p];
    Stencil<Dim, kDamageOrder>(grid_, p_.x[p]).visit([&](int i, Real w, const Vec<Dim>&) {
      grid_.scalar[i] += w * d;
      grid_.scalar_weight[i] += w;
    });
  });
  tbb::parallel_for(size_t(0), grid_.num_active_nodes(), [&](size_t i) {
    if (grid_.scalar_weight[i] > 0) grid_.scalar[i] /= grid_.scalar_weight[i];
  });
  // Laplacian back to the particles, then the update: d grows where the undamaged part of
  // the driving force beats the geometric resistance Dc = d - l0^2 Lap d (which also lets a
  // crack widen to its regularised width l0).
  const auto& order = grid_.order();
  const auto& homes = grid_.home_blocks();
  tbb::parallel_for(size_t(0), homes.size(), [&](size_t b) {
    for (uint32_t k = homes[b].begin; k < homes[b].end; ++k) {
      const uint32_t p = order[k];
      const DamageSpec& ds = damage_[p_.material[p]];
      if (!ds.enabled) continue;
      Real lap = 0;
      if (active[b]) {
        Stencil<Dim, kDamageOrder>(grid_, p_.x[p]).visit_laplacian(
            [&](int i, Real lap_w) { lap += lap_w * grid_.scalar[i]; });
      }
      const Real d = p_.damage[p];
      const Real resistance = d - l0 * l0 * lap;
      const Real drive = (1 - d) * p_.drive[p];
      if (drive > resistance)
        p_.damage[p] = std::min(Real(1), d + dt / Real(ds.eta) * (drive - resistance));
    }
  });
}

template <int Dim>
void MpmSolver<Dim>::damage_implicit(Real dt) {
  // Backward Euler of eta d' = (1 - d) D - (d - l0^2 Lap d) in weak form on the grid
  // (supplement §2.2, Alg. 7-10; EQUATIONS.md §1 "Implicit"):
  //   A_ii = sum_p V_p (1 + k_p (D_p + 1)) w_ip,   k_p = dt / eta_p
  //   B_ij = sum_p V_p k_p l0^2 gradT_i(x_p) . gradT_j(x_p),  gradT_i = M^-1 w_ip (x_i - x_p)
  //   c_i  = sum_p V_p (k_p D_p + d_i^n) w_ip
  // Only damageable particles take part. Particles away from any damage or driving force
  // (see active_damage_blocks) have c = 0 around them and keep d = 0 this step.
  const std::vector<char> active = active_damage_blocks(true);
  if (std::none_of(active.begin(), active.end(), [](char a) { return a != 0; })) return;
  const size_t nodes = grid_.num_active_nodes();
  const Real l2 = Real(scene_.damage.l0 * scene_.damage.l0);
  const Real inv_m = Real(kCubicInvD / (scene_.dx * scene_.dx));
  std::vector<ImplicitNodeSums>& f = implicit_sums_;
  f.assign(nodes, ImplicitNodeSums{});
  laplace_coef_.resize(p_.size());
  for_active_particles_coloured(grid_, active, [&](uint32_t p) {
    const DamageSpec& ds = damage_[p_.material[p]];
    if (!ds.enabled) return;
    const Real V = p_.vol0[p] * std::max(p_.F[p].determinant(), kMinJ);
    const Real k = dt / Real(ds.eta), D = p_.drive[p], d = p_.damage[p];
    const Real a = V * (1 + k * (D + 1)), cd = V * k * D, bl = V * k * l2;
    laplace_coef_[p] = bl * inv_m * inv_m;
    const Real lc = laplace_coef_[p];
    Stencil<Dim, kDamageOrder>(grid_, p_.x[p]).visit([&](int i, Real w,
                                                                  const Vec<Dim>& rel) {
      ImplicitNodeSums& n = f[i];
      n.w += w;
      n.wd += w * d;
      n.a += a * w;
      n.cd += cd * w;
      n.vw += V * w;
      n.bd += lc * w * w * rel.squaredNorm();
    });
  });
  // d_i^n (kept in grid_.scalar for the FLIP transfer), right-hand side, preconditioner.
  grid_.zero_scalar_fields();
  std::vector<Real>& dn = grid_.scalar;
  rhs_.assign(nodes, Real(0));
  inv_diag_.assign(nodes, Real(0));
  solution_.assign(nodes, Real(0));
  tbb::parallel_for(size_t(0), nodes, [&](size_t i) {
    const ImplicitNodeSums& n = f[i];
    if (!(n.w > 0)) return;
    dn[i] = n.wd / n.w;
    rhs_[i] = n.cd + dn[i] * n.vw;
    inv_diag_[i] = 1 / (n.a + n.bd);
    solution_[i] = dn[i];
  });
  // (A + B) x, matrix-free: B x = sum_p c_p gradW_i . (sum_j gradW_j x_j), gathered and
  // scattered per particle (gradW = w (x_i - x_p); c_p = V k l0^2 M^-2 holds the rest).
  auto apply = [&](const std::vector<Real>& x, std::vector<Real>& y) {
    tbb::parallel_for(size_t(0), nodes, [&](size_t i) { y[i] = f[i].a * x[i]; });
    for_active_particles_coloured(grid_, active, [&](uint32_t p) {
      if (!damage_[p_.material[p]].enabled) return;
      const Stencil<Dim, kDamageOrder> st(grid_, p_.x[p]);
      Vec<Dim> g = Vec<Dim>::Zero();
      st.visit([&](int i, Real w, const Vec<Dim>& rel) { g += (w * x[i]) * rel; });
      g *= laplace_coef_[p];
      st.visit([&](int i, Real w, const Vec<Dim>& rel) { y[i] += w * rel.dot(g); });
    });
  };
  const PcgResult res = pcg_solve(apply, rhs_, inv_diag_, scene_.damage.cg_tolerance,
                                  scene_.damage.cg_max_iterations, &solution_);
  DamageSolveStats& s = damage_stats_;
  ++s.solves;
  s.cg_iterations += res.iterations;
  s.cg_iterations_max = std::max(s.cg_iterations_max, res.iterations);
  s.residual_max = std::max(s.residual_max, res.residual);
  s.unconverged += res.converged ? 0 : 1;
  // Back to the particles: FLIP d_p + sum_i w_ip (d_i^{n+1} - d_i^n) (default) or PIC
  // sum_i w_ip d_i^{n+1}, clamped to [d_p^n, 1]: damage never heals.
  const bool flip = scene_.damage.transfer == Transfer::Flip;
  for_active_particles(grid_, active, [&](uint32_t p) {
    if (!damage_[p_.material[p]].enabled) return;
    Real d = flip ? p_.damage[p] : Real(0);
    Stencil<Dim, kDamageOrder>(grid_, p_.x[p]).visit([&](int i, Real w, const Vec<Dim>&) {
      d += w * (flip ? solution_[i] - dn[i] : solution_[i]);
    });
    p_.damage[p] = std::clamp(d, p_.damage[p], Real(1));
  });
}

#define TEAR_DAMAGE_INSTANTIATE(D)                                              \
  template void MpmSolver<D>::damage_step(double);                              \
  template void MpmSolver<D>::damage_update(Real);                              \
  template void MpmSolver<D>::update_driving_force();                           \
  template std::vector<char> MpmSolver<D>::active_damage_blocks(bool) const;    \
  template void MpmSolver<D>::damage_explicit(Real);                            \
  template void MpmSolver<D>::damage_implicit(Real);
TEAR_DAMAGE_INSTANTIATE(2)
TEAR_DAMAGE_INSTANTIATE(3)
#undef TEAR_DAMAGE_INSTANTIATE

}  // namespace tear
