// solvers/: preconditioned conjugate gradients on plain vectors, matrix-free (Jacobi, or any
// preconditioner given as a function).
// Dot products are deterministic sums (exec/parallel.h), so the iterates, and the iteration
// count, are bit-identical for any thread count; a multi-process run sums them over ranks
// (exec/domain.h).
#pragma once

#include "tear/exec/domain.h"
#include "tear/exec/parallel.h"
#include "tear/math/types.h"

#include <cmath>
#include <vector>

namespace tear {

struct PcgResult {
  int iterations = 0;
  double residual = 0;  // final |r| / |b| (0 when b = 0)
  bool converged = false;
};

// Solves K x = b for symmetric positive (semi-)definite K given as apply(x, y): y = K x, with
// the preconditioner precondition(r, z): z = M^-1 r (symmetric positive definite on the active
// unknowns). active(i) says whether unknown i takes part: the residual of the others is held at
// zero, so (with a preconditioner that maps zero to zero there) their entries of x are left
// alone and must not influence the others. x holds the initial guess. Stops when
// |b - K x| <= tolerance |b| or after max_iterations. The vectors are this process's part of the
// system; `domain` sums dot products over the ranks (nullptr: one process).
template <class Apply, class Precondition, class Active>
PcgResult pcg_solve(Apply&& apply, Precondition&& precondition, Active&& active,
                    const std::vector<Real>& b, double tolerance, int max_iterations,
                    std::vector<Real>* x_io, const Domain* domain = nullptr) {
  std::vector<Real>& x = *x_io;
  const size_t n = b.size();
  auto dot = [n, domain](const std::vector<Real>& u, const std::vector<Real>& v) {
    const double local =
        deterministic_sum<double>(n, [&](size_t i) { return double(u[i]) * double(v[i]); });
    return domain ? domain->sum(local) : local;
  };
  auto for_each = [n](auto&& f) { parallel_for(n, f); };

  PcgResult res;
  const double b_norm = std::sqrt(dot(b, b));
  if (b_norm == 0) {
    for_each([&](size_t i) {
      if (active(i)) x[i] = 0;
    });
    return {0, 0, true};
  }
  std::vector<Real> r(n), z(n), p(n), q(n);
  apply(x, q);
  for_each([&](size_t i) { r[i] = active(i) ? b[i] - q[i] : Real(0); });
  precondition(r, z);
  p = z;
  double rz = dot(r, z);
  res.residual = std::sqrt(dot(r, r)) / b_norm;
  while (res.residual > tolerance && res.iterations < max_iterations) {
    apply(p, q);
    const double pq = dot(p, q);
    if (!(pq > 0)) break;  // breakdown (K singular along p): keep the best iterate so far
    const Real step = Real(rz / pq);
    for_each([&](size_t i) {
      x[i] += step * p[i];
      r[i] -= step * q[i];
    });
    precondition(r, z);
    const double rz_new = dot(r, z);
    const Real beta = Real(rz_new / rz);
    rz = rz_new;
    for_each([&](size_t i) { p[i] = z[i] + beta * p[i]; });
    ++res.iterations;
    res.residual = std::sqrt(dot(r, r)) / b_norm;
  }
  res.converged = res.residual <= tolerance;
  return res;
}

// Jacobi-preconditioned: inv_diag holds 1 / K_ii where the unknown takes part and 0 where it
// does not (those entries of x are left alone).
template <class Apply>
PcgResult pcg_solve(Apply&& apply, const std::vector<Real>& b, const std::vector<Real>& inv_diag,
                    double tolerance, int max_iterations, std::vector<Real>* x_io,
                    const Domain* domain = nullptr) {
  const auto jacobi = [&](const std::vector<Real>& r, std::vector<Real>& z) {
    parallel_for(r.size(), [&](size_t i) { z[i] = inv_diag[i] * r[i]; });
  };
  const auto active = [&](size_t i) { return inv_diag[i] != 0; };
  return pcg_solve(apply, jacobi, active, b, tolerance, max_iterations, x_io, domain);
}

}  // namespace tear
