// The sort phase takes the home slots G2P made while it moved the particles (no pass over the
// positions of its own): the binning must be the one a pass over the positions gives, step
// after step, through reorders, for several groups, and where a caller moved particles by hand.
#include "mpm_test_util.h"
#include "tear/mpm/measure.h"
#include "tear/mpm/phases.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace tear {
namespace {
using testing::basic_scene;
using testing::lattice_block;
using testing::MpmSim;

// The state's binning equals a fresh grid's binning of the same positions.
template <int Dim>
void expect_bins_of_positions(const MpmSettings& settings, const MpmState<Dim>& state) {
  SparseGrid<Dim> fresh;
  fresh.setup(settings.domain_min, settings.domain_max, settings.dx);
  std::vector<const std::vector<Vec<Dim>>*> positions;
  for (const Particles<Dim>& g : state.groups) positions.push_back(&g.x);
  fresh.bin(positions);
  ASSERT_EQ(fresh.num_blocks(), state.grid.num_blocks());
  for (size_t g = 0; g < state.groups.size(); ++g) {
    const ParticleBins<Dim>& a = state.grid.bins(g);
    const ParticleBins<Dim>& b = fresh.bins(g);
    EXPECT_EQ(a.particle_slot, b.particle_slot) << "group " << g;
    EXPECT_EQ(a.order, b.order) << "group " << g;
    ASSERT_EQ(a.home_blocks.size(), b.home_blocks.size()) << "group " << g;
    for (size_t h = 0; h < a.home_blocks.size(); ++h) {
      EXPECT_EQ(a.home_blocks[h].slot, b.home_blocks[h].slot);
      EXPECT_EQ(a.home_blocks[h].begin, b.home_blocks[h].begin);
      EXPECT_EQ(a.home_blocks[h].end, b.home_blocks[h].end);
    }
  }
}

// A spinning, drifting block [0.6, 1.1]^Dim (2 particles a cell per axis) in two groups (every
// other particle), each particle's mass times mass(i).
template <int Dim, class Mass>
MpmSim<Dim> spinning_groups(Real drift, Real spin, Mass mass) {
  const Scene s = basic_scene(Dim, 0.05, Vec3d::Zero(), Vec3d::Constant(2.0), Model::FixedCorotated,
                              1e3, 0.3, 1, 3);
  const Vec<Dim> lo = Vec<Dim>::Constant(Real(0.6)), hi = Vec<Dim>::Constant(Real(1.1));
  const Vec<Dim> c = (lo + hi) / 2;
  const Particles<Dim> all = lattice_block<Dim>(s, lo, hi, 2, [&](const Vec<Dim>& x) {
    Vec<Dim> v = Vec<Dim>::Constant(drift);
    v[0] += -spin * (x[1] - c[1]);
    v[1] += spin * (x[0] - c[0]);
    return v;
  });
  std::vector<Particles<Dim>> groups(2);
  for (size_t i = 0; i < all.size(); ++i)
    groups[i % 2].push_back(all.x[i], all.v[i], all.fiber[i], all.mass[i] * mass(i), all.vol0[i],
                            all.material[i]);
  return MpmSim<Dim>(s, std::move(groups));
}

template <int Dim>
void check_sort_uses_g2p_slots() {
  // Fast: particles cross block boundaries every few steps, and the groups are reordered in
  // memory now and then.
  MpmSim<Dim> sim = spinning_groups<Dim>(Real(0.8), Real(6), [](size_t) { return Real(1); });
  const std::vector<uint32_t> ids_before = sim.state().groups[0].id;
  const double dt = sim.estimate_dt();
  constexpr int kSteps = 100;
  int made = 0;
  for (int i = 0; i < kSteps; ++i) {
    sim.step(dt);
    MpmState<Dim>& state = sim.state();
    made += state.home_slots_step == state.steps;
    sort_particles(&state);  // what the next step starts with
    expect_bins_of_positions(sim.settings(), state);
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_EQ(made, kSteps);
  EXPECT_NE(sim.state().groups[0].id, ids_before);  // reordered in memory on the way
  // A caller that moves particles itself says so; the sort then looks at the positions.
  sim.step(dt);
  MpmState<Dim>& state = sim.state();
  for (Vec<Dim>& x : state.groups[1].x) x = (x + Vec<Dim>::Constant(Real(0.2))).eval();
  state.home_slots_step = -1;
  sort_particles(&state);
  expect_bins_of_positions(sim.settings(), state);
}

// A body that drifts across block boundaries now and then: on most steps no particle changes
// home block and the sort keeps the last bins (SparseGrid::bin's shortcut), on the others it
// bins again; either way the bins must be those of the positions, and the node fields P2G adds
// into zero.
template <int Dim>
void check_sort_keeps_bins_where_no_particle_moved() {
  MpmSim<Dim> sim = spinning_groups<Dim>(Real(1), Real(0.5), [](size_t) { return Real(1); });
  const double dt = sim.estimate_dt();
  int kept = 0, changed = 0;
  for (int i = 0; i < 100; ++i) {
    sim.step(dt);
    MpmState<Dim>& state = sim.state();
    ASSERT_EQ(state.home_slots_step, state.steps);
    bool same = true;
    for (size_t g = 0; g < state.groups.size(); ++g)
      same = same && state.home_slots[g] == state.grid.bins(g).particle_slot;
    (same ? kept : changed) += 1;
    SparseGrid<Dim>& grid = state.grid;
    for (size_t n = 0; n < grid.num_active_nodes(); ++n)  // what the step left there
      grid.mass[n] = 1, grid.velocity[n].setOnes(), grid.velocity_old[n].setOnes();
    sort_particles(&state);
    expect_bins_of_positions(sim.settings(), state);
    for (size_t n = 0; n < grid.num_active_nodes(); ++n) {
      ASSERT_EQ(grid.mass[n], 0) << "step " << i << " node " << n;
      ASSERT_TRUE(grid.velocity[n].isZero(0) && grid.velocity_old[n].isZero(0)) << n;
    }
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(kept, 10) << changed;  // the shortcut was taken
  EXPECT_GT(changed, 5) << kept;   // and the full binning too
}

TEST(Sort, BinsKeptWhereNoParticleMovedEqualABinningOfThePositions2D) {
  check_sort_keeps_bins_where_no_particle_moved<2>();
}
TEST(Sort, BinsKeptWhereNoParticleMovedEqualABinningOfThePositions3D) {
  check_sort_keeps_bins_where_no_particle_moved<3>();
}

// G2P's figures of the particles it moved (MpmState::moved) are what a pass over the particles
// gives: the largest squared speed, +inf after a fault, and the smallest mass.
template <int Dim>
void check_g2p_figures() {
  // Masses that differ from particle to particle; the lightest (41) in the second group.
  auto mass = [](size_t i) { return Real(1 + 0.1 * double(i % 7)) / (i == 41 ? 3 : 1); };
  MpmSim<Dim> sim = spinning_groups<Dim>(Real(0.3), Real(4), mass);
  Real lightest = 0;  // particle 41 is the second group's 21st: id 20
  const Particles<Dim>& second = sim.state().groups[1];
  for (size_t k = 0; k < second.size(); ++k)
    if (second.id[k] == 20) lightest = second.mass[k];
  const MpmSettings& settings = sim.settings();
  MpmState<Dim>& state = sim.state();
  auto by_pass = [&](auto figure) {
    const long kept = state.moved_step;
    state.moved_step = -1;
    const Real value = figure();
    state.moved_step = kept;
    return value;
  };
  auto speed2 = [&] { return speed2_or_fault(settings, state); };
  auto min_mass = [&] { return smallest_particle_mass(state); };
  const double dt = sim.estimate_dt();
  for (int i = 0; i < 20; ++i) {
    sim.step(dt);
    ASSERT_EQ(state.moved_step, state.steps);
    EXPECT_EQ(speed2(), by_pass(speed2)) << "step " << i;
    EXPECT_GT(speed2(), 0);
    EXPECT_EQ(min_mass(), by_pass(min_mass)) << "step " << i;
  }
  EXPECT_EQ(min_mass(), lightest);
  EXPECT_GT(lightest, 0);
  // A velocity gone bad: G2P spreads it; both say +inf.
  state.groups[1].v[5][0] = std::numeric_limits<Real>::quiet_NaN();
  state.moved_step = -1;  // changed by hand
  ASSERT_TRUE(std::isinf(speed2()));
  sim.step(dt);
  ASSERT_EQ(state.moved_step, state.steps);
  EXPECT_TRUE(std::isinf(speed2()));
  EXPECT_TRUE(std::isinf(by_pass(speed2)));
}

// KeptBox::speed2_or_fault is +inf exactly where fault_kind finds a fault, and |v|^2 elsewhere.
TEST(Sort, SpeedOrFaultIsInfiniteExactlyForFaults) {
  MpmSettings settings;
  settings.dx = 0.1;
  settings.domain_min = Vec3d::Zero();
  settings.domain_max = Vec3d::Ones();
  const KeptBox<3> kept(settings);
  constexpr Real nan = std::numeric_limits<Real>::quiet_NaN();
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  const Real big = std::sqrt(std::numeric_limits<Real>::max());
  const Vec<3> in(0.5, 0.3, 0.7), v(1, -2, 3);
  const std::vector<Vec<3>> xs = {in,
                                  Vec<3>(0.1, 0.5, 0.5),  // on the low face
                                  Vec<3>(0.5, 0.9, 0.5),  // on the high face
                                  Vec<3>(0.5, 0.5, 0.95),
                                  Vec<3>(nan, 0.5, 0.5),
                                  Vec<3>(0.5, inf, 0.5),
                                  Vec<3>(0.5, 0.5, -inf)};
  const std::vector<Vec<3>> vs = {v, Vec<3>(nan, 0, 0), Vec<3>(0, -inf, 0), Vec<3>(big, big, 0),
                                  Vec<3>::Zero()};
  for (const Vec<3>& x : xs)
    for (const Vec<3>& u : vs) {
      const Real s = kept.speed2_or_fault(x, u);
      const bool fault = kept.fault_kind(x, u) != 0 || !std::isfinite(u.squaredNorm());
      EXPECT_EQ(std::isinf(s), fault) << x.transpose() << " | " << u.transpose();
      if (!fault) {
        EXPECT_EQ(s, u.squaredNorm());
      }
    }
  EXPECT_EQ(kept.speed2_or_fault(in, v), Real(14));
}

TEST(Sort, G2pFiguresEqualAPassOverTheParticles2D) { check_g2p_figures<2>(); }
TEST(Sort, G2pFiguresEqualAPassOverTheParticles3D) { check_g2p_figures<3>(); }

TEST(Sort, BinsFromG2pSlotsEqualABinningOfThePositions2D) { check_sort_uses_g2p_slots<2>(); }
TEST(Sort, BinsFromG2pSlotsEqualABinningOfThePositions3D) { check_sort_uses_g2p_slots<3>(); }

}  // namespace
}  // namespace tear
