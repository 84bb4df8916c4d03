#include "mpm_test_util.h"

#include <gtest/gtest.h>
#include "tear/exec/threads.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>

namespace tear {
namespace {
using testing::MpmSim;

using testing::basic_scene;
using testing::lattice_block;

// A spinning, translating elastic block in free flight (no gravity, no walls).
template <int Dim>
MpmSim<Dim> spinning_block(Transfer transfer) {
  Scene s = basic_scene(Dim, 0.05, Vec3d::Zero(), Vec3d::Constant(2.0), Model::QrAniso, 1e3,
                        0.3, 1, 3);
  s.transfer = transfer;
  Particles<Dim> p = testing::spinning_block<Dim>(s, Vec<Dim>::Constant(Real(0.7)),
                                                  Vec<Dim>::Constant(Real(1.2)));
  return MpmSim<Dim>(s, std::move(p));
}

template <int Dim>
void check_apic_conservation() {
  MpmSim<Dim> sim = spinning_block<Dim>(Transfer::Apic);
  const double m0 = sim.total_mass();
  const Vec3d P0 = sim.momentum(), L0 = sim.angular_momentum();
  for (int i = 0; i < 100; ++i) sim.step(sim.estimate_dt());
  EXPECT_EQ(sim.total_mass(), m0);  // exactly: particles carry mass
  const double scale_p = sim.total_mass() * 1.0, scale_l = L0.norm() + P0.norm();
  EXPECT_LT((sim.momentum() - P0).norm() / scale_p, 1e-12);
  EXPECT_LT((sim.angular_momentum() - L0).norm() / scale_l, 1e-12);
  // The block did spin (2 rad/s for 0.04 s, wave-speed limited steps): not trivially static.
  EXPECT_GT(sim.time(), 0.035);
  EXPECT_GT(sim.kinetic_energy(), 0);
}

TEST(Apic, ConservesLinearAndAngularMomentum2D) { check_apic_conservation<2>(); }
TEST(Apic, ConservesLinearAndAngularMomentum3D) { check_apic_conservation<3>(); }

TEST(Pic, ConservesLinearMomentumButDissipatesRotation) {
  MpmSim<2> sim = spinning_block<2>(Transfer::Pic);
  const Vec3d P0 = sim.momentum(), L0 = sim.angular_momentum();
  for (int i = 0; i < 100; ++i) sim.step(sim.estimate_dt());
  EXPECT_LT((sim.momentum() - P0).norm() / sim.total_mass(), 1e-12);
  // PIC loses angular momentum (the reason APIC is the default).
  EXPECT_LT(std::abs(sim.angular_momentum()[2]), std::abs(L0[2]) * 0.999);
}

TEST(Flip, ConservesLinearMomentum) {
  MpmSim<3> sim = spinning_block<3>(Transfer::Flip);
  const Vec3d P0 = sim.momentum();
  for (int i = 0; i < 50; ++i) sim.step(sim.estimate_dt());
  EXPECT_LT((sim.momentum() - P0).norm() / sim.total_mass(), 1e-12);
}

// A block whose particles alternate up and down (a pattern the grid cannot hold, so only FLIP
// keeps it and the PIC share of each step removes it): the share of kinetic energy left after
// `t_end` with steps of `dt`.
double flip_noise_left(double dt, double ratio, double relaxation_time, double t_end) {
  Scene s =
      basic_scene(2, 0.05, Vec3d::Zero(), Vec3d::Constant(2.0), Model::FixedCorotated, 1, 0.3, 1);
  s.transfer = Transfer::Flip;
  s.flip_ratio = ratio;
  s.flip_relaxation_time = relaxation_time;
  const Real h = Real(s.dx) / 2;
  auto vel = [&](const Vec<2>& x) {
    const long k = std::lround(std::floor(x[0] / h) + std::floor(x[1] / h));
    return Vec<2>(0, k % 2 ? Real(0.3) : Real(-0.3));
  };
  MpmSim<2> sim(s, lattice_block<2>(s, Vec<2>(0.7, 0.7), Vec<2>(1.2, 1.2), 2, vel));
  const double e0 = sim.kinetic_energy();
  while (sim.time() < t_end * (1 - 1e-9)) sim.step(std::min(dt, t_end - sim.time()));
  return sim.kinetic_energy() / e0;
}

TEST(Flip, RelaxationTimeMakesTheBlendIndependentOfTheStep) {
  // flip_ratio acts per step: halving dt doubles the number of blends (0.95^20 vs 0.95^40 of
  // the velocity after 0.02 s).
  const double per_step[] = {flip_noise_left(1e-3, 0.95, 0, 0.02),
                             flip_noise_left(5e-4, 0.95, 0, 0.02)};
  EXPECT_NEAR(per_step[0], std::pow(0.95, 40), 0.1 * std::pow(0.95, 40));
  EXPECT_GT(per_step[0], 4 * per_step[1]);
  // A relaxation time is a rate: the pattern's energy decays as exp(-2 t / tau) for any dt.
  const double tau = 0.01, expected = std::exp(-2 * 0.02 / tau);
  for (double dt : {1e-3, 5e-4, 2.5e-4}) {
    const double left = flip_noise_left(dt, 0.95, tau, 0.02);
    std::printf("  dt %.1e: energy left %.4f (exp(-2 t / tau) = %.4f); per step: %.4f, %.4f\n", dt,
                left, expected, per_step[0], per_step[1]);
    EXPECT_NEAR(left, expected, 0.1 * expected) << "dt " << dt;
    EXPECT_NEAR(left, flip_noise_left(1e-4, 0.95, tau, 0.02), 0.03 * expected) << "dt " << dt;
  }
}

TEST(P2G, GridMassEqualsParticleMass) {
  MpmSim<3> sim = spinning_block<3>(Transfer::Apic);
  sim.step(1e-4);
  double grid_mass = 0;
  for (size_t i = 0; i < sim.grid().num_active_nodes(); ++i) grid_mass += sim.grid().mass[i];
  EXPECT_NEAR(grid_mass, sim.total_mass(), 1e-12 * sim.total_mass());
}

template <int Dim>
std::vector<Real> run_state(int threads) {
  const ThreadLimit limit(threads);
  Scene s = basic_scene(Dim, 0.05, Vec3d::Zero(), Vec3d::Constant(2.0), Model::QrAniso, 1e3,
                        0.3, 1, 3);
  s.walls = ContactType::Separate;
  s.gravity = Vec3d(0, -9.8, 0);
  Particles<Dim> p = lattice_block<Dim>(s, Vec<Dim>::Constant(Real(0.2)),
                                        Vec<Dim>::Constant(Real(0.9)), 2,
                                        [](const Vec<Dim>& x) { return Vec<Dim>(x * 2); });
  MpmSim<Dim> sim(s, std::move(p));
  for (int i = 0; i < 60; ++i) sim.step(sim.estimate_dt());
  std::vector<Real> out;
  for (size_t i = 0; i < sim.particles().size(); ++i) {
    for (int d = 0; d < Dim; ++d) out.push_back(sim.particles().x[i][d]);
    for (int d = 0; d < Dim; ++d) out.push_back(sim.particles().v[i][d]);
    out.push_back(Real(sim.particles().id[i]));
  }
  return out;
}

// Bit equality (NaN compares equal to a NaN with the same bits), naming the first difference.
::testing::AssertionResult same_bits(const std::vector<Real>& a, const std::vector<Real>& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << "sizes " << a.size() << " and " << b.size();
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(Real)) != 0) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "entry %zu of %zu: %.17g vs %.17g", i,
                    a.size(), double(a[i]), double(b[i]));
      return ::testing::AssertionFailure() << buf;
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(Determinism, SameBitsForOneAndTwoThreads2D) {
  EXPECT_TRUE(same_bits(run_state<2>(1), run_state<2>(2)));
}
TEST(Determinism, SameBitsForOneAndTwoThreads3D) {
  EXPECT_TRUE(same_bits(run_state<3>(1), run_state<3>(2)));
}
TEST(Determinism, SameBitsRunToRun) { EXPECT_TRUE(same_bits(run_state<3>(2), run_state<3>(2))); }

}  // namespace
}  // namespace tear

namespace tear {
namespace {

TEST(Stability, BlowUpIsReportedAsAnErrorNotACrash) {
  // A particle whose velocity is NaN spreads it over the grid and its neighbours: the step
  // guard does not redo the step (a shorter one would not mend it), and the next binning
  // says so with a clear error. (2000 steps of 50 or 1000 times the wave speed's limit no
  // longer blow up: the guard halves a step whose velocities would move material more than
  // 2 cfl dx, and once the velocities are that large the shorter steps are stable.)
  MpmSim<2> sim = spinning_block<2>(Transfer::Apic);
  const double dt = sim.estimate_dt();
  sim.particles().v[7][1] = std::numeric_limits<Real>::quiet_NaN();
  try {
    for (int i = 0; i < 3; ++i) sim.step(dt);
    FAIL() << "expected the run to blow up";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unstable"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.steps_redone(), 0);
}

// The guard the driver runs after every step: the particle with the lowest id among those that
// are non-finite or at the domain's edge, whatever the order particles are stored in and for
// any number of threads.
TEST(Stability, ParticleFaultNamesTheLowestIdAndItsKind) {
  MpmSim<3> sim = spinning_block<3>(Transfer::Apic);
  Particles<3>& p = sim.particles();
  ASSERT_FALSE(find_particle_fault(sim.settings(), sim.state()));
  ASSERT_GT(p.size(), 100u);
  // Ids are not memory positions: reverse the storage order.
  std::reverse(p.id.begin(), p.id.end());
  const size_t a = 17, b = p.size() - 40;  // ids size-18 and 39
  p.v[a][1] = std::numeric_limits<Real>::quiet_NaN();
  p.x[b][2] = Real(sim.settings().domain_max[2] - sim.settings().dx);  // on the kept box's face
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    const ParticleFault f = find_particle_fault(sim.settings(), sim.state());
    ASSERT_TRUE(f);
    EXPECT_EQ(f.index, b);
    EXPECT_EQ(f.id, p.id[b]);
    EXPECT_EQ(f.kind, ParticleFault::Kind::LeftDomain);
    EXPECT_EQ(f.material, p.material[b]);
  }
  p.x[b] = p.x[b + 1];  // back inside: the NaN is next
  const ParticleFault f = find_particle_fault(sim.settings(), sim.state());
  EXPECT_EQ(f.id, p.id[a]);
  EXPECT_EQ(f.kind, ParticleFault::Kind::NonFinite);
  EXPECT_TRUE(std::isnan(f.v[1]));
  p.v[a][1] = std::numeric_limits<Real>::infinity();
  EXPECT_EQ(find_particle_fault(sim.settings(), sim.state()).kind, ParticleFault::Kind::NonFinite);
}

}  // namespace
}  // namespace tear
