// The Laplacian of the damage field as the explicit solver computes it from particle data
// (supplement Alg. 4-5): damage to the grid with the normalised cubic B-spline, then
// sum_i d_i LapN_i(x_p) back at the particles. Checked through the solver itself: with no
// driving force, an explicit update is d <- d + dt/eta (l0^2 Lap d - d) wherever that is
// positive, so Lap d can be read back from the change of d. The frame column damage_laplacian
// (scene output.fields) must be that Laplacian.
#include "mpm_test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tear {
namespace {
using testing::MpmSim;

using testing::basic_scene;
using testing::lattice_block;

constexpr double kPi = 3.14159265358979323846;
constexpr double kL0 = 0.5, kEta = 1, kDt = 1e-3;

struct LaplacianError {
  double err = 0;     // largest |Lap d (read back) - exact|
  int compared = 0;   // particles compared
  double stored = 0;  // largest |Particles::damage_laplacian - Lap d (read back)|
};

// Largest |Lap d (read back) - exact| over particles at least 3 cells inside the unit-cube
// block [0.25, 0.75]^Dim, among those the update moved; also how many were compared, and how
// far the field a run writes to its frames (output.fields) is from the read-back Laplacian.
template <int Dim, class Field, class Laplacian>
LaplacianError laplacian_error(double dx, Field f, Laplacian lap) {
  Scene s = basic_scene(Dim, dx, Vec3d::Zero(), Vec3d::Ones(), Model::QrAniso, 100, 0.25, 1);
  s.damage.solver = DamageSolver::Explicit;
  s.damage.l0 = kL0;
  DamageParams& d = s.materials[0].damage;
  d.enabled = true;
  d.sigma_c = 1e9;  // no driving force: F stays the identity anyway
  d.eta = kEta;
  d.residual = 0.001;
  Particles<Dim> p = lattice_block<Dim>(s, Vec<Dim>::Constant(Real(0.25)),
                                        Vec<Dim>::Constant(Real(0.75)), 2,
                                        [](const Vec<Dim>&) { return Vec<Dim>::Zero(); });
  for (size_t i = 0; i < p.size(); ++i) p.damage[i] = Real(f(p.x[i]));
  p.enable("damage_laplacian");
  MpmSim<Dim> sim(s, std::move(p));
  std::vector<Real> before(sim.particles().damage);
  std::vector<uint32_t> id_before(sim.particles().id);
  std::vector<Real> d0(before.size());
  for (size_t i = 0; i < before.size(); ++i) d0[id_before[i]] = before[i];
  sim.damage_step(kDt);
  const Particles<Dim>& q = sim.particles();
  LaplacianError e;
  for (size_t i = 0; i < q.size(); ++i) {
    const Vec<Dim>& x = q.x[i];
    if ((x.array() - 0.5).abs().maxCoeff() > 0.25 - 3 * dx) continue;
    const double old = d0[q.id[i]], now = q.damage[i];
    if (!(now > old)) continue;
    const double lap_read = ((now - old) * kEta / kDt + old) / (kL0 * kL0);
    e.err = std::max(e.err, std::abs(lap_read - lap(x)));
    e.stored = std::max(e.stored, std::abs(double(q.damage_laplacian[i]) - lap_read));
    ++e.compared;
  }
  return e;
}

template <int Dim>
void check_quadratic_is_exact() {
  // f = 0.05 + 0.2 |x - c|^2: Lap f = 0.4 Dim. Lattice particles: the normalised transfer
  // adds a constant times f'' to the nodal values, and the cubic B-spline reproduces
  // quadratics, so the Laplacian is exact up to round-off.
  auto f = [](const Vec<Dim>& x) { return 0.05 + 0.2 * (x.array() - 0.5).square().sum(); };
  auto lap = [](const Vec<Dim>&) { return 0.4 * Dim; };
  for (double dx : {1.0 / 16, 1.0 / 32}) {
    const LaplacianError e = laplacian_error<Dim>(dx, f, lap);
    EXPECT_GT(e.compared, 10);
    EXPECT_LT(e.err, 1e-9) << "dx " << dx;
    // The frame column is the Laplacian the update took (round-off of the read-back aside).
    EXPECT_LT(e.stored, 1e-6) << "dx " << dx;
  }
}

template <int Dim>
void check_cosine_converges_at_second_order() {
  // f = 0.1 - 0.05 prod cos(pi (x - 0.5)): Lap f = -pi^2 Dim (f - 0.1); positive, so every
  // interior particle's damage moves and is compared.
  auto f = [](const Vec<Dim>& x) {
    double c = 1;
    for (int d = 0; d < Dim; ++d) c *= std::cos(kPi * (x[d] - 0.5));
    return 0.1 - 0.05 * c;
  };
  auto lap = [&](const Vec<Dim>& x) { return -kPi * kPi * Dim * (f(x) - 0.1); };
  const auto [coarse, n1, stored1] = laplacian_error<Dim>(1.0 / 16, f, lap);
  const auto [fine, n2, stored2] = laplacian_error<Dim>(1.0 / 32, f, lap);
  EXPECT_LT(std::max(stored1, stored2), 1e-6);
  EXPECT_GT(n1, 10);
  EXPECT_GT(n2, n1);
  const double order = std::log2(coarse / fine);
  EXPECT_GT(order, 1.7) << "errors " << coarse << " " << fine;
  // Measured: order 1.98 in 2D and 3D; errors 0.025 -> 0.0064 (2D), 0.056 -> 0.014 (3D).
  EXPECT_LT(fine, 0.02 * kPi * kPi * Dim * 0.05);  // 2% of the largest |Lap f|
}

TEST(DamageLaplacian, QuadraticFieldFromParticlesIsExact2D) { check_quadratic_is_exact<2>(); }
TEST(DamageLaplacian, QuadraticFieldFromParticlesIsExact3D) { check_quadratic_is_exact<3>(); }
TEST(DamageLaplacian, CosineFieldConvergesAtSecondOrder2D) {
  check_cosine_converges_at_second_order<2>();
}
TEST(DamageLaplacian, CosineFieldConvergesAtSecondOrder3D) {
  check_cosine_converges_at_second_order<3>();
}

}  // namespace
}  // namespace tear
