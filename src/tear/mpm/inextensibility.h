// mpm/: directional inextensibility (paper §6; supplement §1.4 and §4; EQUATIONS.md §3): a
// projection of the grid velocities, after the grid update of either integrator, onto those
// that do not stretch the fibers of inextensible materials.
//
// Each inextensible particle p (weight W_p = (1 - d_p) V_p, V_p = J_p V0_p; none where
// d_p >= 1/2, so that cracks open) has the world fiber a_p = F_p a0_p / s_p, s_p = |F_p a0_p|
// (the direction of its material fiber, the first column of qr_aniso's Q; the paper's R a1
// differs from it under shear and is not a material line). Multipliers live on cell centres
// (linear B-spline Gamma_z), velocities on nodes (quadratic N_i, MLS gradients). One row per
// cell:
//   (B v)_z = sum_p W_p Gamma_z(x_p) a_p^T C_p(v) a_p,  C_p(v) = sum_i v_i grad N_i(x_p)^T,
// the fiber stretch rate of the particles near the cell (G2P's F update is (I + dt C) F), held
// at zero by the hard constraint (the paper's B v = 0; the exact solve leaves a drift of 1e-10
// over thousands of steps in the tests). The relaxed one holds it at the rate that brings the
// fibers back to their rest length over the step,
//   r_z = sum_p W_p Gamma_z(x_p) (1 / s_p^2 - 1) / (2 dt)
// (over the relaxed particles), so that its penalty is on the stretch itself: an elastic fiber.
// Taking r in the hard constraint too is unstable (a run's energy grows until it blows up): the
// rows hold cell averages, which the particles' own stretches cannot all follow at once. A
// cell has no row where the material barely reaches it (V_z = sum_p W_p Gamma_z(x_p) below a tenth of a cell's volume: such a row is a near copy of
// a neighbour's and worsens CG's conditioning by orders of magnitude), nor where walls and
// colliders hold three quarters of it or more (measured by the row's diagonal with and without
// them: its multiplier would grow without moving a node). The new velocities are the closest
// to the grid update's in the mass metric: v = v~ - m^-1 P B^T mu with
// (B m^-1 P B^T + K) mu = B v~ - r, solved by CG preconditioned by that matrix's sparse Cholesky
// factorisation, or its diagonal (P: the directions walls and colliders leave free). K = 0 is the
// hard constraint; the relaxed one (supplement §4.3) has K_zz = sum_p W_p Gamma_z / (k_p dt^2)
// over particles whose material has a relaxation stiffness k_p (Pa): it is the minimiser of
// sum_i m_i/2 |v_i - v~_i|^2 plus the energy k/2 eps^2 V of a fiber of modulus k stretched by
// eps (its stretch after the step), and tends to the hard constraint as k grows.
#pragma once

#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"
#include "tear/solvers/pcg.h"

#include <Eigen/SparseCore>

#include <array>
#include <vector>

namespace tear {

// The figures of the inextensibility solves, summed over steps.
struct InextensibilityStats {
  long solves = 0;
  long cg_iterations = 0;
  int cg_iterations_max = 0;   // of one solve
  double residual_max = 0;     // largest final |B v - r + K mu| / |B v~ - r|
  long unconverged = 0;        // solves stopped at the iteration limit
};

// Whether any material is inextensible.
bool has_inextensibility(const MpmSettings& settings);

// The constraint rows of one step, assembled from the particles and the grid after the grid
// update (grid masses and velocities v~). Exposed for tests.
template <int Dim>
class FiberConstraints {
 public:
  static constexpr int kSlots = Dim == 2 ? 16 : 64;  // nodes a cell's row reaches: 4 per axis

  FiberConstraints(const MpmSettings& settings, const MpmState<Dim>& state, Real dt);

  size_t rows() const { return volume_.size(); }
  // c = B v - r (v: one velocity per grid node).
  void constraint(const std::vector<Vec<Dim>>& v, std::vector<Real>* c) const;
  // u = B^T mu (u: one vector per grid node).
  void transpose(const std::vector<Real>& mu, std::vector<Vec<Dim>>* u) const;
  // The largest |(B v - r)_z| dt / V_z over the rows: the fiber strain left by the step.
  double strain_error(const std::vector<Vec<Dim>>& v) const;
  // Solves for mu (CG from zero: the particles' last tensions, spread back to the cells, are
  // smoother than mu and start CG further from the solution) and corrects v in place; returns
  // CG's figures, and mu in mu_out (when given).
  PcgResult project(std::vector<Vec<Dim>>* v, const InextensibilitySettings& solve,
                    std::vector<Real>* mu_out = nullptr) const;
  // The lower triangle of the Schur complement B m^-1 P B^T + K over the active rows
  // (index[z]: row z's number there, or -1): what the Cholesky preconditioner factors.
  // Exposed for tests.
  Eigen::SparseMatrix<double> schur_matrix(std::vector<int>* index) const;
  // Each particle's fiber tension mu(x_p) / dt (Pa, a Cauchy stress along a_p: the constraint's
  // force is that of the stress (1 - d) T a a^T), 0 where it takes no part, into its
  // fiber_tension field (nothing without one).
  void store_tensions(const std::vector<Real>& mu, Particles<Dim>* p) const;

 private:
  const MpmSettings& settings_;
  const SparseGrid<Dim>& grid_;
  Real dt_;
  std::vector<int> row_of_;  // per node: the row of the cell it is the lower corner of, or -1
  std::vector<int> cell_node_;  // per row: its cell's lower corner node
  std::vector<std::array<int, kSlots>> node_;     // storage index of each slot's node, or -1
  std::vector<std::array<Vec<Dim>, kSlots>> coef_;  // B's entries
  std::vector<Real> volume_, target_, compliance_, diag_;
  std::vector<std::vector<uint32_t>> colours_;  // rows whose node sets are disjoint
  std::vector<Mat<Dim>> mobility_;              // per node: P / m (0 without mass)
};

// The projection of a step: nothing unless a material is inextensible; otherwise the grid
// velocities are corrected (state->grid.velocity) and stats updated.
template <int Dim>
void enforce_inextensibility(const MpmSettings& settings, MpmState<Dim>* state, Real dt,
                             InextensibilityStats* stats);

}  // namespace tear
