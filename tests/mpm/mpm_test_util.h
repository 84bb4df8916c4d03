// Helpers for MPM tests: scenes and particle blocks built in code (no files), and MpmSim, the
// core's settings, state and integrator held together the way the driver holds them.
#pragma once

#include "tear/damage/phase_field.h"
#include "tear/exec/domain.h"
#include "tear/mpm/explicit_step.h"
#include "tear/mpm/implicit_step.h"
#include "tear/mpm/measure.h"
#include "tear/mpm/time_step.h"
#include "tear/scene/sampling.h"
#include "tear/scene/scene.h"

namespace tear::testing {

// A scene's MPM settings and state (one particle group), stepped by the scene's integrator.
template <int Dim>
class MpmSim {
 public:
  // Samples the scene's objects.
  explicit MpmSim(const Scene& scene) : MpmSim(scene, sample_scene<Dim>(scene)) {}
  // Uses the given particles instead.
  MpmSim(const Scene& scene, Particles<Dim> particles)
      : settings_(mpm_settings(scene)),
        state_(make_mpm_state<Dim>(settings_, std::move(particles))) {}
  // Several particle groups.
  MpmSim(const Scene& scene, std::vector<Particles<Dim>> groups)
      : settings_(mpm_settings(scene)), state_(make_mpm_state<Dim>(settings_, std::move(groups))) {}

  void step(double dt) {
    if (settings_.integrator == Integrator::Implicit)
      implicit_step(settings_, &state_, dt, &record_, domain());
    else
      explicit_step(settings_, &state_, dt, &record_, domain());
  }
  // The damage update of one step alone, particles held still.
  void damage_step(double dt) { damage_only_step(settings_, &state_, dt, &record_, domain()); }
  DtLimits dt_limits() const { return tear::dt_limits(settings_, state_, domain()); }
  // Steps through `domain` (which must outlive the steps) instead of a LocalDomain: to see the
  // calls a step makes.
  void use_domain(Domain* domain) { external_ = domain; }
  double estimate_dt() const { return dt_limits().dt(); }
  double damage_dt_limit(bool cracking = false) const {
    return tear::damage_dt_limit(state_.groups, settings_.damage, settings_.material_damage,
                                 settings_.dx, cracking);
  }

  const Particles<Dim>& particles() const { return state_.groups[0]; }
  Particles<Dim>& particles() { return state_.groups[0]; }
  const SparseGrid<Dim>& grid() const { return state_.grid; }
  const MpmSettings& settings() const { return settings_; }
  MpmState<Dim>& state() { return state_; }
  double time() const { return state_.time; }
  void set_time(double t) { state_.time = t; }
  DamageSolveStats& damage_stats() { return record_.damage; }
  ImplicitSolveStats& implicit_stats() { return record_.implicit; }
  InextensibilityStats& inextensibility_stats() { return record_.inextensibility; }
  MpmSettings& mutable_settings() { return settings_; }

  double total_mass() const { return tear::total_mass(state_); }
  Vec3d momentum() const { return total_momentum(state_); }
  Vec3d angular_momentum() const { return total_angular_momentum(settings_, state_); }
  double kinetic_energy() const { return tear::kinetic_energy(state_); }

 private:
  MpmSettings settings_;
  MpmState<Dim> state_;
  StepRecord record_;
  LocalDomain local_;
  Domain* external_ = nullptr;  // not a pointer to local_: an MpmSim may be moved
  Domain& domain() { return external_ ? *external_ : static_cast<Domain&>(local_); }
  const Domain& domain() const {
    return external_ ? *external_ : static_cast<const Domain&>(local_);
  }
};

// A sticky box collider (2D: z ignored) moving at `velocity`.
inline Collider sticky_box(int dim, Vec3d lo, Vec3d hi, Vec3d velocity = Vec3d::Zero()) {
  Collider c;
  c.type = ContactType::Sticky;
  c.shape.type = Shape::Type::Box;
  c.shape.dim = dim;
  c.shape.min = lo;
  c.shape.max = hi;
  c.velocity = velocity;
  return c;
}

inline Scene basic_scene(int dim, double dx, Vec3d lo, Vec3d hi, Model model, double E, double nu,
                         double rho, double fiber_scale = 0) {
  Scene s;
  s.name = "test";
  s.dim = dim;
  s.dx = dx;
  s.domain_min = lo;
  s.domain_max = hi;
  s.walls = ContactType::None;
  s.cfl = 0.4;
  s.max_dt = 1e-2;
  MaterialSpec m;
  m.name = "m";
  m.params = make_material(model, Real(E), Real(nu), Real(rho), Real(fiber_scale), 0);
  m.fiber_scale[0] = Real(fiber_scale);
  s.materials.push_back(m);
  return s;
}

// A regular lattice of k^Dim particles per cell filling [lo, hi] (cell-aligned), fibers
// along x, velocity v(x).
template <int Dim, class VelFn>
Particles<Dim> lattice_block(const Scene& s, const Vec<Dim>& lo, const Vec<Dim>& hi, int k,
                             VelFn vel) {
  Particles<Dim> p;
  const Real h = Real(s.dx) / k;
  IVec<Dim> n;
  for (int d = 0; d < Dim; ++d) n[d] = int(std::lround((hi[d] - lo[d]) / h));
  const Real vol = std::pow(h, Real(Dim));
  const Real rho = s.materials[0].params.rho;
  IVec<Dim> i = IVec<Dim>::Zero();
  while (true) {
    const Vec<Dim> x = lo + (i.template cast<Real>() + Vec<Dim>::Constant(Real(0.5))) * h;
    p.push_back(x, vel(x), Mat<Dim>::Identity(), rho * vol, vol, 0);
    int d = 0;
    while (d < Dim && ++i[d] == n[d]) i[d++] = 0;
    if (d == Dim) break;
  }
  return p;
}

}  // namespace tear::testing
