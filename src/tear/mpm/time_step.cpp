#include "tear/mpm/time_step.h"

#include "tear/codim/bending.h"
#include "tear/damage/phase_field.h"
#include "tear/exec/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tear {

double DtLimits::dt() const { return std::min({max_dt, wave, velocity, damage}); }

const char* DtLimits::limiting() const {
  const double t = dt();
  if (t == max_dt) return "max_dt";
  if (t == wave) return "wave speed";
  if (t == velocity) return "particle speed";
  return "explicit damage";
}

template <int Dim>
DtLimits dt_limits(const MpmSettings& s, const MpmState<Dim>& state, const Domain& domain) {
  Real v2 = 0;
  for (const Particles<Dim>& p : state.groups)
    v2 = std::max(v2, parallel_max<Real>(
                          p.size(), [&](size_t i) { return p.v[i].squaredNorm(); }, Real(0)));
  return dt_limits(s, state, domain, v2);
}

template <int Dim>
DtLimits dt_limits(const MpmSettings& s, const MpmState<Dim>& state, const Domain& domain,
                   Real v2) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  DtLimits l;
  l.max_dt = s.max_dt;
  Real c = 0;
  for (const MaterialParams& m : s.materials) c = std::max(c, wave_speed(m));
  // Bending (codim/bending.h): its stiffest resolved mode as a wave speed, per body.
  if (s.integrator == Integrator::Explicit)
    for (const Particles<Dim>& p : state.groups) c = std::max(c, bending_wave_speed(s.materials, p, s.dx));
  // The implicit integrator is not limited by the wave speed (only by max_dt, the particle
  // speed's displacement CFL and, with explicit damage, its limit).
  l.wave = c > 0 && s.integrator == Integrator::Explicit ? s.cfl * s.dx / c : kNone;
  const Real vmax = std::sqrt(Real(domain.max(double(v2))));
  l.velocity = vmax > 0 ? s.cfl * s.dx / vmax : kNone;
  l.damage = domain.min(damage_dt_limit(state.groups, s.damage, s.material_damage, s.dx, false));
  l.damage_cracking = damage_dt_limit(state.groups, s.damage, s.material_damage, s.dx, true);
  return l;
}

template DtLimits dt_limits<2>(const MpmSettings&, const MpmState<2>&, const Domain&);
template DtLimits dt_limits<3>(const MpmSettings&, const MpmState<3>&, const Domain&);
template DtLimits dt_limits<2>(const MpmSettings&, const MpmState<2>&, const Domain&, Real);
template DtLimits dt_limits<3>(const MpmSettings&, const MpmState<3>&, const Domain&, Real);

}  // namespace tear
