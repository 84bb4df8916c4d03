// mpm/: the implicit (backward Euler) integrator beside the explicit one: the same phases,
// with the grid update's forces replaced by the minimisation of the incremental potential over
// the grid velocities (Gast et al. 2015), by Newton's method (solvers/newton.h).
#pragma once

#include "tear/codim/bending.h"
#include "tear/exec/domain.h"
#include "tear/mpm/explicit_step.h"
#include "tear/mpm/settings.h"
#include "tear/mpm/state.h"
#include "tear/solvers/multigrid.h"
#include "tear/solvers/newton.h"

#include <array>
#include <memory>
#include <vector>

namespace tear {

// One backward Euler step of size dt from state->time to state->time + dt:
//   sort, stress and damage (as the explicit step), P2G of mass and momentum without the stress,
//   v* = momentum / mass + dt g with walls and colliders, then the grid velocities v minimise
//     E(v) = sum_i m_i/2 |v_i - v*_i|^2 + sum_p V_p Psi(F_p(v)),
//     F_p(v) = (I + dt sum_i v_i grad w_ip^T) F_p,  grad w_ip = D^-1 w_ip (x_i - x_p) (MLS),
//   whose gradient is the explicit step's momentum balance with the stress at the end of the
//   step; colliders and walls hold their nodes' constrained components (sticky: all, slip: the
//   normal one, separate: the normal one where the node approaches) at v*'s; then colliders
//   again (friction), G2P and the plastic projection. Codimensional elements (codim/) enter
//   with their F(v) from their corners: the tangent columns from the corners' positions moved by
//   their interpolated velocities, the normal columns advected by the corners' mean velocity
//   gradient, as G2P will make them (so the potential's gradient at v* is the explicit step's
//   force). Crack fields (damage.split_fields) are not supported (the scene refuses them). One process only: `domain` must be local. Redone with a
// smaller dt where its velocities would move material too far, as every step
// (integrate_step, mpm/explicit_step.h); returns the dt taken.
template <int Dim>
double implicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                     StepRecord* record, Domain& domain);

// The incremental potential of one step over the grid velocities (flattened: Dim entries per
// grid node, nodes in storage order), as solvers/newton.h's problem. Built after P2G and the
// grid update of the step (grid masses and v* in state.grid.velocity); holds references to
// `state`. Exposed for tests.
template <int Dim>
class IncrementalPotential {
 public:
  IncrementalPotential(const MpmSettings& settings, const MpmState<Dim>& state, Real dt);

  // v*: the starting point, which satisfies the constraints.
  const std::vector<Real>& initial() const { return v_star_; }

  double energy(const std::vector<Real>& v);
  void gradient(const std::vector<Real>& v, std::vector<Real>& g);
  // max over nodes of |g_i| / max(m_i, m_floor) (a velocity error) over dx / dt: Newton's
  // stopping measure. m_floor is a hundredth of the mean node mass: at nodes that the material
  // barely reaches (masses down to 1e-8 of a particle's at a body's edge) |g_i| / m_i is
  // round-off of the stress forces, which no Newton step reduces (a stiff femur stalled there
  // at 5x the tolerance for 100 iterations); such a node's velocity reaches the particles with
  // its tiny weight only.
  double residual(const std::vector<Real>& g) const;
  void prepare_hessian(const std::vector<Real>& v);
  void apply_hessian(const std::vector<Real>& d, std::vector<Real>& y) const;
  // Multigrid or Jacobi (settings.implicit_preconditioner), built by prepare_hessian.
  void precondition(const std::vector<Real>& r, std::vector<Real>& z) const;
  // Auto, before the switch: builds the multigrid hierarchy at the current Hessian, used from
  // then on (the rest of this solve, the step's later Newton iterations and, through
  // MpmState::implicit_multigrid, later steps).
  // Never with codimensional elements: their corners' stencils reach farther than the
  // assembled matrix's 5-node neighbourhood, so they run with Jacobi.
  bool can_strengthen_preconditioner() const {
    return settings_.implicit_preconditioner == ImplicitPreconditioner::Auto && !use_multigrid_ &&
           !codim_;
  }
  void strengthen_preconditioner();
  // Newton iterations whose linear solve used multigrid (for part of it, under auto).
  int multigrid_solves() const { return multigrid_solves_; }
  // The matrix apply_hessian applies (after prepare_hessian), assembled, with the identity on
  // the constrained directions and on nodes without mass: what the multigrid preconditioner
  // coarsens. Row node * Dim + a: node's component a. Exposed for tests. Not with
  // codimensional elements (throws std::logic_error).
  Eigen::SparseMatrix<double, Eigen::RowMajor> hessian_matrix() const;
  // The multigrid hierarchy of the last prepare_hessian (null with Jacobi).
  const LatticeMultigrid<Dim>* multigrid() const { return multigrid_.get(); }
  bool active(size_t i) const { return mass_[i / Dim] > 0; }

  // Removes the constrained components (and those of nodes without mass) of a velocity-sized
  // vector.
  void project(std::vector<Real>& u) const;

 private:
  static constexpr int kStencil = Dim == 2 ? 9 : 27;
  struct ParticleRef {
    uint32_t group, index;
  };
  // F_p(v) for every particle.
  void deformations(const std::vector<Real>& v);
  template <class Fn>
  void scatter(Fn&& fn) const;  // fn(flat particle, add(node, vector)) in a deterministic order
  Real degradation_of(const ParticleRef& r) const;
  // Codimensional bodies. Each mesh vertex gathers a grid vector u (its interpolated value and
  // gradient, into vertex_u_ / vertex_G_); each element's rate dF/dt is linear in its corners'
  // gathers; the element matrices in element_load_ (V P, or its differential) load their
  // vertices (vertex_f_, vertex_S_: the force and normal-stress terms of codim/elements.h),
  // which the scatter spreads like the explicit P2G. Indices: flat ref - codim_begin_.
  void gather_vertices(const std::vector<Real>& u) const;
  Mat<Dim> element_rate(size_t k) const;
  void load_vertices() const;
  void scatter_vertex(size_t k, std::vector<Real>& out) const;  // out += dt (f w + S grad w)
  // Bending (codim/bending.h): each hinge's gradient at the vertices' end-of-step positions
  // (vertex_x_), or its Hessian times dt times the gathered direction, added to vertex_f_.
  void load_hinges(bool hessian) const;
  bool is_kind(size_t k, GroupKind kind) const { return state_.groups[refs_[k].group].kind == kind; }

  const MpmSettings& settings_;
  const MpmState<Dim>& state_;
  Real dt_;
  std::vector<size_t> group_offset_;
  std::vector<ParticleRef> refs_;
  std::vector<Real> degradation_;
  std::vector<std::array<int, kStencil>> nodes_;  // stencil nodes of each particle
  std::vector<std::array<Vec<Dim>, kStencil>> grads_;  // F^T grad w for each
  std::vector<Mat<Dim>> F_;  // F_p(v) of the last evaluation
  std::vector<StressDerivative<Dim>> hessian_;  // projected V0 dP/dF of each particle
  std::vector<Real> mass_, v_star_, diag_;
  Real residual_mass_ = 0;  // residual(): the mass floor
  std::vector<Mat<Dim>> free_;  // per node: projection onto the unconstrained directions
  mutable std::vector<Real> scratch_;
  bool codim_ = false;
  size_t codim_begin_ = 0;
  std::vector<size_t> elements_;  // flat refs of the element particles
  std::vector<std::array<Real, kStencil>> weights_;  // vertices: w of each stencil node
  mutable std::vector<Vec<Dim>> vertex_u_, vertex_f_;
  mutable std::vector<Mat<Dim>> vertex_G_, vertex_S_, element_load_, element_normal_load_;
  mutable std::vector<Vec<Dim>> vertex_x_;  // vertices: x + dt u of the last deformations()
  std::vector<std::vector<CurveHingeHessian<Dim>>> hinge_hessian_;  // per group: curves', projected
  mutable std::vector<Vec<Dim>> hinge_load_;  // per hinge corner
  void build_multigrid();
  std::vector<IVec<Dim>> node_coords() const;  // each grid node's integer coordinates
  Eigen::SparseMatrix<double, Eigen::RowMajor> assemble_hessian(
      const std::vector<IVec<Dim>>& coord) const;
  std::unique_ptr<LatticeMultigrid<Dim>> multigrid_;
  bool use_multigrid_ = false;  // multigrid at the next prepare_hessian
  int multigrid_solves_ = 0;
  int multigrid_age_ = 0;  // Newton iterations the hierarchy has served
  mutable Eigen::VectorXd mg_r_, mg_z_;
};

}  // namespace tear
