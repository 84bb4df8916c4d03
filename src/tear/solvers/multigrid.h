// solvers/: a geometric multigrid preconditioner for symmetric positive (semi-)definite systems
// whose unknowns sit on a sparse set of integer lattice points (grid nodes, cell centres), a
// block of unknowns per point. Knows nothing of MPM: the implicit integrator's Newton solves and
// the inextensibility solve are its users.
//
// Levels: each coarse lattice has spacing twice the finer one's; a fine point's value is
// interpolated (multilinearly) from the coarse points around it (p even along an axis: the one
// at p/2; odd: the two at (p -+ 1)/2, weight 1/2 each), and coarse matrices are Galerkin
// products A_c = P^T A P, so no level needs to know where the matrix came from. Smoothing is
// multicolour Gauss-Seidel: points coloured by their coordinates modulo (reach + 1) share no
// entry, so each colour is relaxed in parallel and the result does not depend on the thread
// count. Forward sweeps before the coarse correction and the same sweeps backward after it make
// the V-cycle symmetric, and Gauss-Seidel converges for any symmetric positive definite A, so
// the cycle is a symmetric positive definite operator: a valid CG preconditioner. The coarsest
// level is solved by a sparse Cholesky factorisation. Measured against l1-Jacobi smoothing on
// the implicit integrator's Hessian (fiber_scale 50, dt 40x the explicit limit): 14, 20, 27
// CG iterations as dx halves twice, against 65, 104, 236.
#pragma once

#include "tear/math/types.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <vector>

namespace tear {

struct MultigridSettings {
  int smoothing = 2;     // Gauss-Seidel sweeps before and after each coarse correction
  int coarsest = 800;    // a level with at most this many unknowns is factored
  int max_levels = 20;
};

template <int Dim>
class LatticeMultigrid {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

  // points[k]: the integer coordinates of point k, whose unknowns are rows k block ... k block +
  // block - 1 of A. reach (1 to 3): the largest distance along an axis between two points that
  // share an entry of A (2 for quadratic B-spline nodes, 3 for the inextensibility rows). free: empty, or block x block column-major matrices, one per point: each
  // point's orthogonal projection onto its free directions (constraints held by the caller);
  // the coarse levels see the free directions only, and apply() projects its result. A's rows
  // for the constrained directions should hold the identity there.
  // A is taken (left empty).
  LatticeMultigrid(const std::vector<IVec<Dim>>& points, int block, int reach, Matrix&& A,
                   const std::vector<double>& free = {}, const MultigridSettings& settings = {});

  // z = one V-cycle applied to r: an approximation of A^-1 r, a symmetric positive definite
  // operator of r.
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

  int levels() const { return int(levels_.size()); }
  // Unknowns on each level, finest first.
  std::vector<long> sizes() const;

 private:
  struct Level {
    Matrix A;
    std::vector<std::vector<int>> colours;  // points no two of which share an entry
    Matrix P, R;             // to this level from the next coarser one, and its transpose
    mutable Eigen::VectorXd x, b, r;
  };
  void cycle(size_t level) const;  // levels_[level].x from levels_[level].b
  // Gauss-Seidel sweeps over the colours, in order (forward) or in reverse: the forward sweeps
  // before the coarse correction and the backward ones after it make the cycle symmetric.
  void smooth(const Level& l, bool forward) const;

  int block_;
  std::vector<double> free_;
  std::vector<Level> levels_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> coarse_;
  bool factored_ = false;
  MultigridSettings settings_;
};

// y = A x, rows in parallel, each summed in storage order.
void sparse_multiply(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
                     const Eigen::VectorXd& x, Eigen::VectorXd& y);

}  // namespace tear
