#include "tear/mpm/measure.h"

#include "tear/damage/driving_force.h"
#include "tear/exec/parallel.h"
#include "tear/mpm/phases.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace tear {

namespace {
// Sum over the groups (in order) of each group's deterministic sum of f(group, i); one group's
// sum is returned as it is (no 0 + x, which would turn -0 into +0).
template <int Dim, class T, class Fn>
T sum_groups(const MpmState<Dim>& state, Fn&& f, T zero = T{}) {
  if (state.groups.empty()) return zero;
  auto group_sum = [&](const Particles<Dim>& p) {
    return deterministic_sum<T>(
        p.size(), [&](size_t i) { return f(p, i); }, zero);
  };
  T total = group_sum(state.groups[0]);
  for (size_t g = 1; g < state.groups.size(); ++g) total += group_sum(state.groups[g]);
  return total;
}

// Each figure's term for particle i, shared by the figures one at a time (for tests) and by
// measure_state's one pass over the particles.
template <int Dim>
double mass_term(const Particles<Dim>& p, size_t i) {
  return double(p.mass[i]);
}

template <int Dim>
Vec3d momentum_term(const Particles<Dim>& p, size_t i) {
  Vec3d m = Vec3d::Zero();
  m.head<Dim>() = (p.mass[i] * p.v[i]).template cast<double>();
  return m;
}

// About the origin, with APIC's affine part.
template <int Dim>
struct AngularMomentumTerm {
  bool apic;
  double k;  // dx^2 / 4: D = k I
  explicit AngularMomentumTerm(const MpmSettings& settings)
      : apic(settings.transfer == Transfer::Apic),
        k(settings.dx * settings.dx / BSpline1D<kTransferOrder>::kInvD) {}
  Vec3d operator()(const Particles<Dim>& p, size_t i) const {
    Vec3d x = Vec3d::Zero(), v = Vec3d::Zero();
    x.head<Dim>() = p.x[i].template cast<double>();
    v.head<Dim>() = p.v[i].template cast<double>();
    const double m = p.mass[i];
    Vec3d L = m * x.cross(v);
    if (apic) {
      Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
      C.topLeftCorner<Dim, Dim>() = p.C[i].template cast<double>();
      // sum_i w (x_i - x_p) x C (x_i - x_p) = k (C_32 - C_23, C_13 - C_31, C_21 - C_12)
      L += m * k * Vec3d(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
    }
    return L;
  }
};

template <int Dim>
double kinetic_term(const Particles<Dim>& p, size_t i) {
  return 0.5 * double(p.mass[i] * p.v[i].squaredNorm());
}

template <int Dim>
double elastic_term(const MpmSettings& settings, const Particles<Dim>& p, size_t i) {
  const DamageParams& dp = settings.material_damage[p.material[i]];
  const Real g = dp.enabled ? degradation(p.damage[i], Real(dp.residual)) : Real(1);
  return double(p.vol0[i] *
                energy_density<Dim>(settings.materials[p.material[i]], p.F[i], p.fiber_of(i), g));
}

// measure_state's sums (and the largest damage), added figure by figure: each figure gets
// the same additions in the same order as its own deterministic sum would make.
struct FigureSums {
  double mass = 0;
  Vec3d momentum = Vec3d::Zero(), angular_momentum = Vec3d::Zero();
  double kinetic = 0, elastic = 0, damage = 0, damaged = 0, max_damage = 0;
  FigureSums& operator+=(const FigureSums& o) {
    mass += o.mass;
    momentum += o.momentum;
    angular_momentum += o.angular_momentum;
    kinetic += o.kinetic;
    elastic += o.elastic;
    damage += o.damage;
    damaged += o.damaged;
    max_damage = std::max(max_damage, o.max_damage);
    return *this;
  }
};

}  // namespace

template <int Dim>
double total_mass(const MpmState<Dim>& state) {
  return sum_groups<Dim, double>(state, mass_term<Dim>);
}

template <int Dim>
Vec3d total_momentum(const MpmState<Dim>& state) {
  return sum_groups<Dim, Vec3d>(state, momentum_term<Dim>, Vec3d::Zero());
}

template <int Dim>
Vec3d total_angular_momentum(const MpmSettings& settings, const MpmState<Dim>& state) {
  return sum_groups<Dim, Vec3d>(state, AngularMomentumTerm<Dim>(settings), Vec3d::Zero());
}

template <int Dim>
double kinetic_energy(const MpmState<Dim>& state) {
  return sum_groups<Dim, double>(state, kinetic_term<Dim>);
}

template <int Dim>
double elastic_energy(const MpmSettings& settings, const MpmState<Dim>& state) {
  return sum_groups<Dim, double>(
      state, [&](const Particles<Dim>& p, size_t i) { return elastic_term(settings, p, i); });
}

template <int Dim>
StateFigures measure_state(const MpmSettings& settings, const MpmState<Dim>& state) {
  const AngularMomentumTerm<Dim> angular(settings);
  const FigureSums sums = sum_groups<Dim, FigureSums>(state, [&](const Particles<Dim>& p,
                                                                 size_t i) {
    FigureSums t;
    t.mass = mass_term(p, i);
    t.momentum = momentum_term(p, i);
    t.angular_momentum = angular(p, i);
    t.kinetic = kinetic_term(p, i);
    t.elastic = elastic_term(settings, p, i);
    t.damage = double(p.damage[i]);
    t.damaged = p.damage[i] > 0.5 ? 1.0 : 0.0;
    t.max_damage = p.damage[i];
    return t;
  });
  StateFigures s;
  s.particles = state.num_particles();
  s.mass = sums.mass;
  s.momentum = sums.momentum;
  s.angular_momentum = sums.angular_momentum;
  s.kinetic_energy = sums.kinetic;
  s.elastic_energy = sums.elastic;
  if (const size_t n = s.particles) {
    s.max_damage = sums.max_damage;
    s.mean_damage = sums.damage / double(n);
    s.damaged_fraction = sums.damaged / double(n);
  }
  return s;
}

StateFigures reduce_figures(const StateFigures& local, const Domain& domain) {
  if (domain.ranks() == 1) return local;
  const double n = double(local.particles);
  // Sums of all ranks; the damage means as sums of per-particle values.
  double sums[12] = {n,
                     local.mass,
                     local.kinetic_energy,
                     local.elastic_energy,
                     local.mean_damage * n,
                     local.damaged_fraction * n};
  for (int k = 0; k < 3; ++k)
    sums[6 + k] = local.momentum[k], sums[9 + k] = local.angular_momentum[k];
  domain.sum(sums, 12);
  StateFigures s;
  s.particles = size_t(sums[0]);
  s.mass = sums[1];
  s.kinetic_energy = sums[2];
  s.elastic_energy = sums[3];
  s.mean_damage = sums[0] > 0 ? sums[4] / sums[0] : 0;
  s.damaged_fraction = sums[0] > 0 ? sums[5] / sums[0] : 0;
  for (int k = 0; k < 3; ++k) s.momentum[k] = sums[6 + k], s.angular_momentum[k] = sums[9 + k];
  s.max_damage = domain.max(local.max_damage);
  return s;
}

template <int Dim>
Real speed2_or_fault(const MpmSettings& settings, const MpmState<Dim>& state) {
  if (state.moved_step == state.steps) return state.moved.speed2;  // G2P's, no second pass
  const KeptBox<Dim> kept(settings);
  Real v2 = 0;
  for (const Particles<Dim>& p : state.groups)
    v2 = std::max(v2, parallel_max<Real>(
                          p.size(), [&](size_t i) { return kept.speed2_or_fault(p.x[i], p.v[i]); },
                          Real(0)));
  return v2;
}

template <int Dim>
ParticleFault find_particle_fault(const MpmSettings& settings, const MpmState<Dim>& state) {
  const KeptBox<Dim> kept(settings);
  ParticleFault fault;
  for (size_t g = 0; g < state.groups.size(); ++g) {
    const Particles<Dim>& p = state.groups[g];
    // One pass for "is there one" (the common answer is no), the lowest id only then.
    auto kind = [&](size_t i) { return kept.fault_kind(p.x[i], p.v[i]); };
    if (!parallel_any(p.size(), [&](size_t i) { return kind(i) != 0; })) continue;
    const int64_t lowest = -parallel_max<int64_t>(
        p.size(), [&](size_t i) { return kind(i) ? -int64_t(p.id[i]) : INT64_MIN; },
        INT64_MIN);
    for (size_t i = 0; i < p.size(); ++i) {
      if (int64_t(p.id[i]) != lowest) continue;
      if (fault && p.id[i] >= fault.id) break;  // an earlier group's is lower
      fault.group = int(g);
      fault.index = i;
      fault.id = p.id[i];
      fault.material = p.material[i];
      fault.kind =
          kind(i) == 2 ? ParticleFault::Kind::NonFinite : ParticleFault::Kind::LeftDomain;
      fault.x.head<Dim>() = p.x[i].template cast<double>();
      fault.v.head<Dim>() = p.v[i].template cast<double>();
      break;
    }
  }
  return fault;
}

#define TEAR_MEASURE_INSTANTIATE(D)                                                      \
  template double total_mass<D>(const MpmState<D>&);                                     \
  template Vec3d total_momentum<D>(const MpmState<D>&);                                  \
  template Vec3d total_angular_momentum<D>(const MpmSettings&, const MpmState<D>&);      \
  template double kinetic_energy<D>(const MpmState<D>&);                                 \
  template double elastic_energy<D>(const MpmSettings&, const MpmState<D>&);             \
  template StateFigures measure_state<D>(const MpmSettings&, const MpmState<D>&);        \
  template ParticleFault find_particle_fault<D>(const MpmSettings&, const MpmState<D>&); \
  template Real speed2_or_fault<D>(const MpmSettings&, const MpmState<D>&);
TEAR_MEASURE_INSTANTIATE(2)
TEAR_MEASURE_INSTANTIATE(3)
#undef TEAR_MEASURE_INSTANTIATE

}  // namespace tear
