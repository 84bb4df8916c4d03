// Particle groups: a body split into two groups moves as it does in one (to round-off: only
// the order of the grid sums differs), and momentum is still conserved.
#include "mpm_test_util.h"

#include <gtest/gtest.h>

#include <map>

namespace tear {
namespace {
using testing::basic_scene;
using testing::lattice_block;
using testing::MpmSim;

template <int Dim>
Particles<Dim> spinning_particles(const Scene& s) {
  Vec<Dim> lo = Vec<Dim>::Constant(Real(0.7)), hi = Vec<Dim>::Constant(Real(1.2));
  const Vec<Dim> c = (lo + hi) / 2;
  auto vel = [&](const Vec<Dim>& x) {
    Vec<Dim> v = Vec<Dim>::Constant(Real(0.3));
    v[0] += -Real(2) * (x[1] - c[1]);
    v[1] += Real(2) * (x[0] - c[0]);
    return v;
  };
  return lattice_block<Dim>(s, lo, hi, 2, vel);
}

// The particles with even (part 0) or odd (part 1) index, ids kept.
template <int Dim>
Particles<Dim> part(const Particles<Dim>& all, int which) {
  Particles<Dim> out;
  for (size_t i = size_t(which); i < all.size(); i += 2) {
    out.push_back(all.x[i], all.v[i], all.fiber[i], all.mass[i], all.vol0[i], all.material[i]);
    out.id.back() = all.id[i];
  }
  return out;
}

template <int Dim>
void check_two_groups_move_as_one() {
  Scene s =
      basic_scene(Dim, 0.05, Vec3d::Zero(), Vec3d::Constant(2.0), Model::QrAniso, 1e3, 0.3, 1, 3);
  const Particles<Dim> all = spinning_particles<Dim>(s);
  MpmSim<Dim> one(s, all);
  MpmSim<Dim> two(s, std::vector<Particles<Dim>>{part(all, 0), part(all, 1)});
  const Vec3d P0 = two.momentum(), L0 = two.angular_momentum();
  const double dt = one.estimate_dt();
  ASSERT_EQ(dt, two.estimate_dt());
  for (int i = 0; i < 60; ++i) one.step(dt), two.step(dt);
  std::map<uint32_t, Vec<Dim>> x_one;
  for (size_t i = 0; i < one.particles().size(); ++i)
    x_one[one.particles().id[i]] = one.particles().x[i];
  double worst = 0;
  size_t seen = 0;
  for (const Particles<Dim>& g : two.state().groups)
    for (size_t i = 0; i < g.size(); ++i, ++seen)
      worst = std::max(worst, double((g.x[i] - x_one.at(g.id[i])).norm()));
  EXPECT_EQ(seen, all.size());
  EXPECT_LT(worst, 1e-9 * s.dx);  // round-off of a different summation order
  // The two runs really moved (0.3 m/s for 60 steps).
  EXPECT_GT((one.particles().x[0] - all.x[0]).norm(), 0.1 * s.dx);
  const double scale = two.total_mass() + L0.norm() + P0.norm();
  EXPECT_LT((two.momentum() - P0).norm() / scale, 1e-12);
  EXPECT_LT((two.angular_momentum() - L0).norm() / scale, 1e-12);
}

TEST(Groups, TwoGroupsMoveAsOneBody2D) { check_two_groups_move_as_one<2>(); }
TEST(Groups, TwoGroupsMoveAsOneBody3D) { check_two_groups_move_as_one<3>(); }

}  // namespace
}  // namespace tear
