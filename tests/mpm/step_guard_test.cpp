// The step guard (integrate_step, mpm/explicit_step.h): a step whose grid velocities would carry
// material further than kRedoCflFactor * cfl * dx is redone with a smaller dt, from the state it
// began with.
#include "mpm_test_util.h"

#include <gtest/gtest.h>

#include <cstring>

namespace tear {
namespace {

using testing::basic_scene;
using testing::lattice_block;
using testing::MpmSim;
using testing::sticky_box;

constexpr double kDx = 1.0 / 32;

// A damageable qr_aniso block [0.3, 0.7] x [0.3, 0.5] at rest, stretched along x by F(0,0) =
// 1.3 (so that the damage update has a driving force in the first step), 2x2 particles a cell;
// a sticky box over its left end moves along +x at `speed`.
MpmSim<2> pushed_block(Integrator integrator, DamageSolver solver, double speed) {
  Scene s = basic_scene(2, kDx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::QrAniso, 100, 0.25, 2);
  s.integrator = integrator;
  s.damage.solver = solver;
  s.damage.l0 = kDx / 2;
  s.damage.zeta = 1;
  s.damage.tolerance = 1e-12;
  DamageParams& d = s.materials[0].damage;
  d.enabled = solver != DamageSolver::None;
  d.sigma_c = 10;
  d.eta = 0.05;
  d.residual = 0.001;
  s.boundaries.push_back(
      sticky_box(2, Vec3d(0.25, 0.25, 0), Vec3d(0.4, 0.55, 0), Vec3d(speed, 0, 0)));
  Particles<2> p = lattice_block<2>(s, Vec<2>(0.3, 0.3), Vec<2>(0.7, 0.5), 2,
                                    [](const Vec<2>&) { return Vec<2>::Zero(); });
  for (auto& F : p.F) F(0, 0) = Real(1.3);
  return MpmSim<2>(s, std::move(p));
}

// Every restartable field of the particles, by id, as bytes.
std::vector<Real> state_of(const MpmSim<2>& sim) {
  const Particles<2>& p = sim.particles();
  std::vector<Real> out(p.size() * 14);
  for (size_t i = 0; i < p.size(); ++i) {
    Real* o = &out[size_t(p.id[i]) * 14];
    for (int k = 0; k < 2; ++k) o[k] = p.x[i][k], o[2 + k] = p.v[i][k];
    for (int k = 0; k < 4; ++k) o[4 + k] = p.F[i](k % 2, k / 2), o[8 + k] = p.C[i](k % 2, k / 2);
    o[12] = p.damage[i];
    o[13] = p.drive.empty() ? 0 : p.drive[i];  // optional: only with damage
  }
  return out;
}

struct Case {
  Integrator integrator;
  DamageSolver solver;
  const char* name;
};

const Case kCases[] = {{Integrator::Explicit, DamageSolver::Explicit, "explicit, explicit damage"},
                       {Integrator::Explicit, DamageSolver::Implicit, "explicit, implicit damage"},
                       {Integrator::Implicit, DamageSolver::Explicit, "implicit, explicit damage"},
                       {Integrator::Explicit, DamageSolver::None, "explicit, no damage"}};

TEST(StepGuard, AStepThatWouldMoveMaterialTooFarIsRedoneAsIfTakenShortFromTheStart) {
  // The planned dt (the wave speed's, or max_dt 1e-2 for the implicit integrator) with a grip
  // moving at 40: 40 dt / dx = 1.6 (explicit) or 12.8 cells, over the limit 2 * 0.4. The step
  // is redone with dt = min(dt / 2, cfl dx / 40) and leaves the state bit for bit as a step of
  // that dt taken at once; damage grows in that step, so the damage fields were put back.
  const double speed = 40;
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    MpmSim<2> redone = pushed_block(c.integrator, c.solver, speed);
    MpmSim<2> direct = pushed_block(c.integrator, c.solver, speed);
    const double planned = redone.estimate_dt();
    ASSERT_GT(speed * planned, kRedoCflFactor * 0.4 * kDx);
    const std::vector<Real> before = state_of(redone);
    const double taken = redone.step(planned);
    EXPECT_EQ(redone.steps_redone(), 1);
    EXPECT_EQ(taken, std::min(planned / 2, 0.4 * kDx / speed));
    EXPECT_EQ(redone.time(), taken);
    EXPECT_EQ(direct.step(taken), taken);
    EXPECT_EQ(direct.steps_redone(), 0);
    const std::vector<Real> a = state_of(redone), b = state_of(direct);
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Real)));
    // No particle moved more than the limit; the grip's moved cfl dx.
    double moved = 0, damage = 0;
    for (size_t i = 0; i < a.size() / 14; ++i) {
      moved = std::max(moved,
                       std::hypot(a[i * 14] - before[i * 14], a[i * 14 + 1] - before[i * 14 + 1]));
      damage = std::max(damage, double(a[i * 14 + 12]));
    }
    EXPECT_LE(moved, kRedoCflFactor * 0.4 * kDx);
    EXPECT_NEAR(moved, 0.4 * kDx, 1e-3 * kDx);
    if (c.solver != DamageSolver::None) {
      EXPECT_GT(damage, 0) << "no damage: the test would not see the fields put back";
    }
  }
}

TEST(StepGuard, SlowStepsAreNotRedone) {
  // A grip at 1: every planned step stays under the limit and is taken as planned.
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    MpmSim<2> sim = pushed_block(c.integrator, c.solver, 1);
    for (int k = 0; k < 5; ++k) {
      const double planned = sim.estimate_dt();
      EXPECT_EQ(sim.step(planned), planned);
    }
    EXPECT_EQ(sim.steps_redone(), 0);
  }
}

TEST(StepGuard, FreeFallAtTheParticleSpeedLimitIsNotRedone) {
  // Under strong gravity the particles' speed soon sets dt (cfl dx / max|v|), and each step
  // speeds them up by g dt: the step ends a little over cfl, never over twice it.
  Scene s = basic_scene(2, kDx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::NeoHookean, 100, 0.25, 2);
  s.gravity = Vec3d(0, -200, 0);
  MpmSim<2> sim(s, lattice_block<2>(s, Vec<2>(0.4, 0.7), Vec<2>(0.6, 0.9), 2,
                                    [](const Vec<2>&) { return Vec<2>(0, -2); }));
  int velocity_limited = 0;
  while (sim.time() < 0.05) {
    const DtLimits l = sim.dt_limits();
    if (l.dt() == l.velocity) ++velocity_limited;
    sim.step(l.dt());
  }
  EXPECT_GT(velocity_limited, 10);
  EXPECT_EQ(sim.steps_redone(), 0);
}

}  // namespace
}  // namespace tear
