// solvers/: Newton's method for minimising a smooth energy over plain vectors, with a
// positive semi-definite Hessian approximation solved by preconditioned CG (pcg.h) and a
// backtracking line search on the energy. Deterministic like pcg.h. Knows nothing of MPM: the
// implicit integrator (mpm/implicit_step.cpp) is its first user.
#pragma once

#include "tear/solvers/pcg.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

namespace tear {

struct NewtonSettings {
  double tolerance = 1e-5;     // stop when problem.residual(gradient) <= tolerance
  int max_iterations = 20;     // Newton iterations
  double cg_tolerance = 1e-3;  // relative residual of each linear solve
  int cg_max_iterations = 1000;
  // > 0: a linear solve still short of cg_tolerance after this many iterations switches to the
  // problem's stronger preconditioner, where it offers one, and goes on from where it stopped.
  int cg_escalate_after = 200;
};

struct NewtonResult {
  int iterations = 0;      // Newton steps taken
  long cg_iterations = 0;  // summed over the steps
  int line_search_cuts = 0;  // step halvings, summed over the steps
  int escalations = 0;       // linear solves that switched to a stronger preconditioner
  double residual = 0;     // problem.residual of the last gradient
  bool converged = false;
  std::vector<double> residuals;  // residual before each step and at the end (tests, stats)
  std::vector<double> energies;   // energy before each step and at the end
};

template <class P, class = void>
struct HasStrengthenPreconditioner : std::false_type {};
template <class P>
struct HasStrengthenPreconditioner<
    P, std::void_t<decltype(std::declval<P&>().can_strengthen_preconditioner()),
                   decltype(std::declval<P&>().strengthen_preconditioner())>> : std::true_type {};

// Minimises problem.energy(x) from the initial x. The problem provides, on vectors of x's size:
//   double energy(const std::vector<Real>& x)
//   void gradient(const std::vector<Real>& x, std::vector<Real>& g)    (constrained entries 0)
//   double residual(const std::vector<Real>& g)    the convergence measure of a gradient
//   void prepare_hessian(const std::vector<Real>& x)   before apply_hessian at this x
//   void apply_hessian(const std::vector<Real>& d, std::vector<Real>& y)  y = H d, PSD, with
//        the constraints applied (constrained entries of y 0, d's ignored)
//   void precondition(const std::vector<Real>& r, std::vector<Real>& z)
//   bool active(size_t i)     whether unknown i takes part
// and optionally
//   bool can_strengthen_preconditioner()  whether a stronger (costlier) preconditioner exists
//   void strengthen_preconditioner()      switch to it at the current Hessian
//        (see NewtonSettings::cg_escalate_after)
// Each step solves H d = -g by PCG from d = 0, then halves the step from 1 until the energy does
// not increase (to round-off) (at most 30 halvings; past them the step is taken at the last length, counted in
// line_search_cuts). A descent direction is guaranteed by H being PSD and CG starting at 0.
template <class Problem>
NewtonResult newton_minimize(Problem& problem, std::vector<Real>* x_io,
                             const NewtonSettings& settings) {
  std::vector<Real>& x = *x_io;
  const size_t n = x.size();
  NewtonResult res;
  std::vector<Real> g(n), b(n), d(n), trial(n);
  double energy = problem.energy(x);
  while (true) {
    problem.gradient(x, g);
    res.residual = problem.residual(g);
    res.residuals.push_back(res.residual);
    res.energies.push_back(energy);
    if (res.residual <= settings.tolerance) {
      res.converged = true;
      break;
    }
    if (res.iterations >= settings.max_iterations) break;
    problem.prepare_hessian(x);
    parallel_for(n, [&](size_t i) {
      b[i] = -g[i];
      d[i] = 0;
    });
    const auto solve = [&](int max_iterations) {
      return pcg_solve(
          [&](const std::vector<Real>& u, std::vector<Real>& y) { problem.apply_hessian(u, y); },
          [&](const std::vector<Real>& r, std::vector<Real>& z) { problem.precondition(r, z); },
          [&](size_t i) { return problem.active(i); }, b, settings.cg_tolerance, max_iterations,
          &d);
    };
    int budget = settings.cg_max_iterations;
    bool escalate = false;
    if constexpr (HasStrengthenPreconditioner<Problem>::value)
      escalate = settings.cg_escalate_after > 0 && settings.cg_escalate_after < budget &&
                 problem.can_strengthen_preconditioner();
    PcgResult cg = solve(escalate ? settings.cg_escalate_after : budget);
    res.cg_iterations += cg.iterations;
    if constexpr (HasStrengthenPreconditioner<Problem>::value) {
      if (escalate && !cg.converged) {
        problem.strengthen_preconditioner();
        ++res.escalations;
        cg = solve(budget - cg.iterations);  // from the d reached so far
        res.cg_iterations += cg.iterations;
      }
    }
    Real alpha = 1;
    double trial_energy = 0;
    for (int cut = 0;; ++cut) {
      parallel_for(n, [&](size_t i) { trial[i] = x[i] + alpha * d[i]; });
      trial_energy = problem.energy(trial);
      // Round-off in a sum of many energies: a change below 1e-13 of it counts as none.
      if (trial_energy <= energy + 1e-13 * std::abs(energy) || cut == 30) break;
      alpha /= 2;
      ++res.line_search_cuts;
    }
    x.swap(trial);
    energy = trial_energy;
    ++res.iterations;
  }
  return res;
}

}  // namespace tear
