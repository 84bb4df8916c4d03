// mpm/: the plain settings of an MPM simulation: grid, time step limits, transfer, gravity,
// walls and colliders, materials and damage. scene/ fills them from a scene file; the solver
// never sees the scene.
#pragma once

#include "tear/damage/damage_settings.h"
#include "tear/grid/collider.h"
#include "tear/materials/material.h"
#include "tear/materials/plasticity.h"
#include "tear/math/types.h"
#include "tear/solvers/newton.h"

#include <vector>

namespace tear {

enum class Transfer { Apic, Pic, Flip };

// explicit: symplectic Euler (mpm/explicit_step.h); implicit: backward Euler by Newton on the
// incremental potential (mpm/implicit_step.h).
enum class Integrator { Explicit, Implicit };

// Directional inextensibility of a material's fibers (mpm/inextensibility.h).
struct InextensibleParams {
  bool enabled = false;
  // > 0: the relaxed constraint, a penalty with this fiber stiffness (Pa); 0: the hard one.
  double relaxation = 0;
};

// The preconditioner of the implicit integrator's linear solves: geometric multigrid on the
// grid nodes, Galerkin-coarsened from the assembled Hessian (solvers/multigrid.h), or the
// Hessian's diagonal (cheap per iteration; its iterations grow with dt / dx). Auto: the
// diagonal until a solve has taken newton.cg_escalate_after iterations without converging,
// multigrid from then on (for the rest of the run: MpmState::implicit_multigrid).
enum class ImplicitPreconditioner { Auto, Multigrid, Jacobi };

// The inextensibility solve: CG on the multipliers until |residual| <= tolerance |B v~ - r|,
// preconditioned by the Schur complement's sparse Cholesky factorisation (exact: one or two
// iterations; its cost grows faster than the rows, most in 3D) or its diagonal. (Geometric
// multigrid on the cells, solvers/multigrid.h, was tried: 77 iterations a step on the hanging
// disk against Jacobi's 377 and Cholesky's 1, slower than Cholesky: rows across a thin rope
// are nearly dependent, which point smoothers do not resolve.)
enum class InextensibilityPreconditioner { Cholesky, Jacobi };
struct InextensibilitySettings {
  double tolerance = 1e-6;
  int max_iterations = 2000;
  InextensibilityPreconditioner preconditioner = InextensibilityPreconditioner::Cholesky;
};

struct MpmSettings {
  // Grid: nodes at domain_min + i dx; particles are kept one cell inside the domain.
  double dx = 0.01;
  Vec3d domain_min = Vec3d::Zero(), domain_max = Vec3d::Ones();  // z ignored in 2D
  // Time step: dt = min(max_dt, cfl dx / wave speed (explicit integrator only), cfl dx / max|v|,
  // the explicit damage limit) (ARCHITECTURE.md "One explicit step").
  double cfl = 0.4;
  double max_dt = 1e-3;
  Vec3d gravity = Vec3d::Zero();
  Transfer transfer = Transfer::Apic;
  Integrator integrator = Integrator::Explicit;
  NewtonSettings newton;  // the implicit integrator's solve
  ImplicitPreconditioner implicit_preconditioner = ImplicitPreconditioner::Auto;
  double flip_ratio = 0.95;
  // > 0: FLIP's per-step ratio is exp(-dt / flip_relaxation_time) instead of flip_ratio, so
  // particle velocities relax to the grid's at a rate that does not depend on the step.
  double flip_relaxation_time = 0;
  // Boundaries: the domain walls (ContactType::None: no walls) and analytic colliders.
  ContactType walls = ContactType::Separate;
  std::vector<Collider> colliders;
  // Materials, indexed by a particle's material id: the constitutive model, its damage
  // parameters (enabled = false: never damaged) and its plasticity (YieldSurface::None: elastic;
  // may be empty when no material is plastic).
  std::vector<MaterialParams> materials;
  std::vector<DamageParams> material_damage;
  std::vector<PlasticParams> material_plasticity;
  // Inextensibility of each material (may be empty when no material is inextensible) and its
  // solve.
  std::vector<InextensibleParams> material_inextensibility;
  InextensibilitySettings inextensibility;
  DamageSettings damage;
};

}  // namespace tear
