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

  // One step of dt, or shorter where it had to be redone; returns the dt taken.
  double step(double dt) {
    return settings_.integrator == Integrator::Implicit
               ? implicit_step(settings_, &state_, dt, &record_, domain())
               : explicit_step(settings_, &state_, dt, &record_, domain());
  }
  long steps_redone() const { return record_.steps_redone; }
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

// A spinning, translating block filling [lo, hi] (2 x 2 (x 2) particles a cell): velocity
// 0.3 along every axis plus a spin of 2 rad/s about z through its centre; fibers turned 0.4 rad
// (about z in 2D, about (1, 2, 3) in 3D) so that it is anisotropic in a generic direction.
template <int Dim>
Particles<Dim> spinning_block(const Scene& s, const Vec<Dim>& lo, const Vec<Dim>& hi) {
  const Vec<Dim> c = (lo + hi) / 2;
  Particles<Dim> p = lattice_block<Dim>(s, lo, hi, 2, [&](const Vec<Dim>& x) {
    Vec<Dim> v = Vec<Dim>::Constant(Real(0.3));
    v[0] += -Real(2) * (x[1] - c[1]);
    v[1] += Real(2) * (x[0] - c[0]);
    return v;
  });
  for (auto& D : p.fiber) {
    if constexpr (Dim == 2) {
      D = Eigen::Rotation2D<Real>(Real(0.4)).toRotationMatrix();
    } else {
      D = Eigen::AngleAxis<Real>(Real(0.4), Vec<3>(1, 2, 3).normalized()).toRotationMatrix();
    }
  }
  return p;
}

// A fixed-free bar along x (length 1 from x = 0.25, 4 cells high, 2x2 particles a cell, E, nu
// = 0, rho = 1), clamped by a sticky box over x <= 0.25 and released in its first
// longitudinal mode with peak speed 1e-3 c: it rings at sqrt(E_eff / rho) / 4.
inline MpmSim<2> clamped_bar(Model model, double E, double dx, double fiber_scale,
                             Integrator integrator = Integrator::Explicit) {
  constexpr double kPi = 3.14159265358979323846;
  const double x0 = 0.25, L = 1;
  Scene s = basic_scene(2, dx, Vec3d(0, 0, 0), Vec3d(1.5, 0.5, 0), model, E, 0.0, 1.0,
                        fiber_scale);
  s.integrator = integrator;
  s.boundaries.push_back(sticky_box(2, Vec3d(-1, -1, 0), Vec3d(x0 + 1e-9, 2, 0)));
  const double v0 = 1e-3 * wave_speed(s.materials[0].params);
  auto vel = [&](const Vec<2>& x) {
    return Vec<2>(Real(v0 * std::sin(kPi * (x[0] - x0) / (2 * L))), 0);
  };
  Particles<2> p = lattice_block<2>(s, Vec<2>(Real(x0), Real(0.2)),
                                    Vec<2>(Real(x0 + L), Real(0.2 + 4 * dx)), 2, vel);
  return MpmSim<2>(s, std::move(p));
}

// Steps sim to t_end by dt(sim) and returns the times at which the mean x-velocity of its
// particles changed sign (interpolated within a step).
template <class StepSize>
std::vector<double> velocity_zero_crossings(MpmSim<2>& sim, double t_end, StepSize dt) {
  auto mean_v = [&] {
    double m = 0;
    for (size_t i = 0; i < sim.particles().size(); ++i) m += sim.particles().v[i][0];
    return m / double(sim.particles().size());
  };
  std::vector<double> crossings;
  double prev = mean_v(), t_prev = sim.time();
  while (sim.time() < t_end) {
    sim.step(dt(sim));
    const double cur = mean_v();
    if ((prev > 0) != (cur > 0))
      crossings.push_back(t_prev + (sim.time() - t_prev) * prev / (prev - cur));
    prev = cur, t_prev = sim.time();
  }
  return crossings;
}

}  // namespace tear::testing
