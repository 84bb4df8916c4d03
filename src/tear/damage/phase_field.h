// damage/: the phase-field damage update of one step (EQUATIONS.md §1) over particle groups
// and the sparse grid: the driving force with history, then the explicit or implicit solver.
// Both solvers integrate the same semi-discrete law on the particles,
//   eta d_p' = < (1 - d_p) D_p - (d_p - l0^2 (L d)_p) >,
// where (L d)_p = sum_i LapN_i(x_p) d_i is the Laplacian of the normalised cubic B-spline
// average d_i = sum_q w_iq d_q / sum_q w_iq (supplement Alg. 4); with an anisotropic crack
// surface (DamageParams::surface) it is sum_i (M_p : grad grad N_i(x_p)) d_i instead. Explicit:
// forward Euler (paper Eq. 11). Implicit: backward Euler, solved for the particles' damage by
// sweeps (docs/materials.md "Damage solvers"), so that it tends to the explicit result as dt
// shrinks.
#pragma once

#include "tear/damage/damage_settings.h"
#include "tear/exec/domain.h"
#include "tear/grid/sparse_grid.h"
#include "tear/particles/particles.h"

#include <vector>

namespace tear {

// The damage update of one step: the driving force from the stress and J of this step (the
// constitutive phase's, Particles::stress and ::J), then `settings.solver`; nothing with
// DamageSolver::None. `params` per material; the grid's binning must be of the current
// positions. Implicit solves are counted in `stats`. `domain` sums and copies the halos of the
// damage field's grid transfer in a multi-process run.
template <int Dim>
void update_damage(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                   const DamageSettings& settings, const std::vector<DamageParams>& params,
                   double dt, DamageSolveStats* stats, Domain& domain);

// Driving force with history, Dtilde_p = max(Dtilde_p^H, zeta <Phi_p - 1>) (EQUATIONS.md §1),
// for every damageable particle. Returns whether any particle has a driving force or damage
// (else the damage update has nothing to do).
template <int Dim>
bool update_driving_force(std::vector<Particles<Dim>>* groups,
                          const std::vector<DamageParams>& params, double zeta);

// Explicit phase-field damage (supplement Alg. 3-5): damage to the grid with the cubic
// B-spline, its Laplacian back, forward Euler update.
template <int Dim>
void damage_explicit(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                     const std::vector<DamageParams>& params, Real l0, Real dt, Domain& domain);

// Implicit phase-field damage: backward Euler of the same law for the particles' damage,
// solved by Jacobi sweeps.
template <int Dim>
void damage_implicit(std::vector<Particles<Dim>>* groups, SparseGrid<Dim>* grid,
                     const DamageSettings& settings, const std::vector<DamageParams>& params,
                     Real dt, DamageSolveStats* stats, Domain& domain);

// The particles' damage on the grid, grid->scalar: d_i = sum_p w_ip d_p / sum_p w_ip with the
// B-spline of order `Order` (3: the field whose Laplacian the damage update takes; 2: the
// sharper one the crack-field phase takes gradients of); 0 where no damaged particle is near.
// Overwrites grid->scalar_weight (the weights). Halos are summed and copied through `domain`.
// Returns, per group and home block (grid->bins(g).home_blocks), whether the block is near
// damage: elsewhere every particle is undamaged and its stencil sees only d_i = 0.
template <int Order, int Dim>
std::vector<std::vector<char>> damage_on_grid(const std::vector<Particles<Dim>>& groups,
                                              SparseGrid<Dim>* grid, Domain& domain);

// Driving forces above this count as this in the explicit step limit (the overshoot they could
// cause is below 1 / (1 + kDriveCap)).
constexpr double kDriveCap = 99;
// Spectral radius of l0^2 L (the particles' damage Laplacian) per (2 l0 / dx)^2: 0.26-0.35
// measured on lattice and random samplings in 2D and 3D, rounded up.
constexpr double kLaplacianRadius = 0.4;

// The explicit damage update's step limit, eta / (1 + min(D, kDriveCap) + 4 dim l0^2 / dx^2 s)
// over the damageable particles not yet fully cracked (s = DamageParams::surface_factor(), 1
// for the paper's isotropic surface term); with `cracking`, the limit once a crack
// grows (D = kDriveCap). Infinity for the implicit solver and without damage.
template <int Dim>
double damage_dt_limit(const std::vector<Particles<Dim>>& groups, const DamageSettings& settings,
                       const std::vector<DamageParams>& params, double dx, bool cracking);

}  // namespace tear
