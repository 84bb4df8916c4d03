#include "tear/mpm/solver.h"

#include "tear/damage/driving_force.h"
#include "tear/grid/collider.h"
#include "tear/math/parallel.h"
#include "tear/scene/sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace tear {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
// Reorder particles in memory when this fraction changed home block since the last reorder.
constexpr double kReorderFraction = 0.1;
// Quadratic B-spline: the MPM transfer kernel (MLS-MPM, Hu et al. 2018).
constexpr int kOrder = 2;
}  // namespace

template <int Dim>
MpmSolver<Dim>::MpmSolver(const Scene& scene) : MpmSolver(scene, sample_scene<Dim>(scene)) {}

template <int Dim>
MpmSolver<Dim>::MpmSolver(const Scene& scene, Particles<Dim> particles)
    : scene_(scene), p_(std::move(particles)) {
  for (const MaterialSpec& m : scene_.materials) {
    mats_.push_back(m.params);
    damage_.push_back(m.damage);
  }
  gravity_ = scene_.gravity.template head<Dim>().template cast<Real>();
  grid_.setup(scene_.domain_min, scene_.domain_max, scene_.dx);
  for (int d = 0; d < Dim; ++d) {
    lo_[d] = Real(scene_.domain_min[d] + scene_.dx);
    hi_[d] = Real(scene_.domain_max[d] - scene_.dx);
  }
  slot_at_permute_.clear();
  sort_particles();
}

template <int Dim>
void MpmSolver<Dim>::restore(Particles<Dim> particles, std::vector<int> slots_at_reorder,
                             double time, long steps) {
  p_ = std::move(particles);
  slot_at_permute_ = std::move(slots_at_reorder);
  time_ = time;
  steps_ = steps;
}

double DtLimits::dt() const { return std::min({max_dt, wave, velocity, damage}); }

const char* DtLimits::limiting() const {
  const double t = dt();
  if (t == max_dt) return "max_dt";
  if (t == wave) return "wave speed";
  if (t == velocity) return "particle speed";
  return "explicit damage";
}

template <int Dim>
DtLimits MpmSolver<Dim>::dt_limits() const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const double dx = scene_.dx;
  DtLimits l;
  l.max_dt = scene_.max_dt;
  Real c = 0;
  for (const MaterialParams& m : mats_) c = std::max(c, wave_speed(m));
  l.wave = c > 0 ? scene_.cfl * dx / c : kNone;
  const Real vmax = std::sqrt(parallel_max<Real>(
      p_.size(), [&](size_t i) { return p_.v[i].squaredNorm(); }, Real(0)));
  l.velocity = vmax > 0 ? scene_.cfl * dx / vmax : kNone;
  l.damage = damage_dt_limit();
  l.damage_cracking = damage_dt_limit(true);
  return l;
}

template <int Dim>
void MpmSolver<Dim>::sort_particles() {
  grid_.bin(p_.x);
  const std::vector<int>& slot = grid_.particle_slot();
  size_t moved = slot.size();
  if (slot_at_permute_.size() == slot.size()) {
    moved = deterministic_sum<size_t>(
        slot.size(), [&](size_t i) { return size_t(slot[i] != slot_at_permute_[i]); });
  }
  if (double(moved) > kReorderFraction * double(slot.size())) {
    p_.permute(grid_.order());
    grid_.bin(p_.x);
    slot_at_permute_ = grid_.particle_slot();
  }
}

template <int Dim>
Real MpmSolver<Dim>::degradation_of(size_t p) const {
  const DamageSpec& d = damage_[p_.material[p]];
  return d.enabled ? degradation(p_.damage[p], Real(d.residual)) : Real(1);
}

template <int Dim>
Mat<Dim> MpmSolver<Dim>::stress_for_p2g(size_t p) const {
  const MaterialParams& mat = mats_[p_.material[p]];
  const Mat<Dim>& F = p_.F[p];
  // Damageable particles (qr_aniso only: the scene refuses damage on other models) reuse the
  // undegraded stress of this step's driving force, degraded without a second QR.
  if (piola_fresh_ && damage_[p_.material[p]].enabled && F.determinant() > 0)
    return p_.damage[p] == 0 ? piola_[p]
                             : degrade_qr_stress<Dim>(mat, F, piola_[p], degradation_of(p));
  return first_piola<Dim>(mat, F, p_.fiber[p], degradation_of(p));
}

template <int Dim>
void MpmSolver<Dim>::p2g(Real dt) {
  const Real inv_d = BSpline1D<kOrder>::kInvD / Real(scene_.dx * scene_.dx);
  const bool apic = scene_.transfer == Transfer::Apic;
  const bool flip = scene_.transfer == Transfer::Flip;
  const auto& order = grid_.order();
  const auto& homes = grid_.home_blocks();
  for (int c = 0; c < SparseGrid<Dim>::kColours; ++c) {
    const std::vector<int>& blocks = grid_.colour(c);
    tbb::parallel_for(size_t(0), blocks.size(), [&](size_t b) {
      const auto& h = homes[blocks[b]];
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t p = order[k];
        const Mat<Dim>& F = p_.F[p];
        const Mat<Dim> P = stress_for_p2g(p);
        // MLS-MPM: the stress enters as an affine momentum term (Hu et al. 2018, Eq. 29).
        Mat<Dim> affine = (-dt * p_.vol0[p] * inv_d) * (P * F.transpose());
        const Real m = p_.mass[p];
        if (apic) affine += m * p_.C[p];
        const Vec<Dim> mv = m * p_.v[p];
        Stencil<Dim, kOrder>(grid_, p_.x[p]).visit([&](int node, Real w,
                                                                const Vec<Dim>& rel) {
          grid_.mass[node] += w * m;
          // mv + affine (x_i - x_p), column by column: Eigen's product temporaries here
          // cost store-forwarding stalls.
          Vec<Dim> dv = mv;
          for (int c = 0; c < Dim; ++c) dv += affine.col(c) * rel[c];
          grid_.velocity[node] += w * dv;
          if (flip) grid_.velocity_old[node] += w * mv;  // force-free momentum
        });
      }
    });
  }
}

template <int Dim>
void MpmSolver<Dim>::grid_update(Real dt) {
  tbb::parallel_for(0, grid_.num_blocks(), [&](int blk) {
    const int a = blk * SparseGrid<Dim>::kNodesPerBlock;
    for (int node = a; node < a + SparseGrid<Dim>::kNodesPerBlock; ++node) {
      const Real m = grid_.mass[node];
      if (m <= 0) {
        grid_.velocity[node].setZero();
        grid_.velocity_old[node].setZero();
        continue;
      }
      // MLS puts the stress impulse into the momentum already; velocity_old holds the
      // force-free momentum, so FLIP differences carry stress, gravity and boundaries.
      grid_.velocity[node] /= m;
      grid_.velocity_old[node] /= m;
      grid_.velocity[node] += dt * gravity_;
    }
  });
  apply_colliders<Dim>(grid_, scene_.walls, scene_.boundaries, time_);
}

template <int Dim>
void MpmSolver<Dim>::g2p(Real dt) {
  const Real inv_d = BSpline1D<kOrder>::kInvD / Real(scene_.dx * scene_.dx);
  const bool flip = scene_.transfer == Transfer::Flip;
  const Real ratio =
      Real(scene_.flip_relaxation_time > 0 ? std::exp(-double(dt) / scene_.flip_relaxation_time)
                                           : scene_.flip_ratio);
  tbb::parallel_for(size_t(0), p_.size(), [&](size_t p) {
    Vec<Dim> v = Vec<Dim>::Zero(), v_old = Vec<Dim>::Zero();
    Mat<Dim> B = Mat<Dim>::Zero();
    Stencil<Dim, kOrder>(grid_, p_.x[p]).visit([&](int node, Real w,
                                                            const Vec<Dim>& rel) {
      const Vec<Dim> wv = w * grid_.velocity[node];
      v += wv;
      for (int c = 0; c < Dim; ++c) B.col(c) += wv * rel[c];  // B += wv (x_i - x_p)^T
      if (flip) v_old += w * grid_.velocity_old[node];
    });
    const Mat<Dim> C = B * inv_d;  // velocity gradient estimate (APIC B D^-1)
    p_.C[p] = C;
    p_.F[p] = (Mat<Dim>::Identity() + dt * C) * p_.F[p];
    p_.v[p] = flip ? Vec<Dim>(ratio * (p_.v[p] + v - v_old) + (1 - ratio) * v) : v;
    p_.x[p] = (p_.x[p] + dt * v).cwiseMax(lo_).cwiseMin(hi_);
  });
}

template <int Dim>
void MpmSolver<Dim>::step(double dt) {
  auto t0 = Clock::now();
  sort_particles();
  times_.sort += seconds_since(t0);
  if (scene_.damage.solver != DamageSolver::None) {
    t0 = Clock::now();
    damage_update(Real(dt));
    times_.damage += seconds_since(t0);
  }
  t0 = Clock::now();
  p2g(Real(dt));
  piola_fresh_ = false;
  times_.p2g += seconds_since(t0);
  t0 = Clock::now();
  grid_update(Real(dt));
  times_.grid += seconds_since(t0);
  t0 = Clock::now();
  g2p(Real(dt));
  times_.g2p += seconds_since(t0);
  time_ += dt;
  ++steps_;
}

template <int Dim>
double MpmSolver<Dim>::total_mass() const {
  return deterministic_sum<double>(p_.size(), [&](size_t i) { return double(p_.mass[i]); });
}

template <int Dim>
Vec3d MpmSolver<Dim>::momentum() const {
  return deterministic_sum<Vec3d>(
      p_.size(),
      [&](size_t i) {
        Vec3d m = Vec3d::Zero();
        m.head<Dim>() = (p_.mass[i] * p_.v[i]).template cast<double>();
        return m;
      },
      Vec3d::Zero());
}

template <int Dim>
Vec3d MpmSolver<Dim>::angular_momentum() const {
  const bool apic = scene_.transfer == Transfer::Apic;
  const double k = scene_.dx * scene_.dx / BSpline1D<kOrder>::kInvD;  // D = (dx^2 / 4) I
  return deterministic_sum<Vec3d>(
      p_.size(),
      [&](size_t i) {
        Vec3d x = Vec3d::Zero(), v = Vec3d::Zero();
        x.head<Dim>() = p_.x[i].template cast<double>();
        v.head<Dim>() = p_.v[i].template cast<double>();
        const double m = p_.mass[i];
        Vec3d L = m * x.cross(v);
        if (apic) {
          Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
          C.topLeftCorner<Dim, Dim>() = p_.C[i].template cast<double>();
          // sum_i w (x_i - x_p) x C (x_i - x_p) = k (C_32 - C_23, C_13 - C_31, C_21 - C_12)
          L += m * k * Vec3d(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
        }
        return L;
      },
      Vec3d::Zero());
}

template <int Dim>
double MpmSolver<Dim>::kinetic_energy() const {
  return deterministic_sum<double>(
      p_.size(), [&](size_t i) { return 0.5 * double(p_.mass[i] * p_.v[i].squaredNorm()); });
}

template <int Dim>
double MpmSolver<Dim>::elastic_energy() const {
  return deterministic_sum<double>(p_.size(), [&](size_t i) {
    return double(p_.vol0[i] * energy_density<Dim>(mats_[p_.material[i]], p_.F[i], p_.fiber[i],
                                                   degradation_of(i)));
  });
}

template class MpmSolver<2>;
template class MpmSolver<3>;

}  // namespace tear
