// Fixed-free elastic bar (nu = 0): the first longitudinal mode has frequency
// f = sqrt(E_eff / rho) / (4 L). A velocity field shaped like that mode is released and the
// period of the bar's mean velocity is measured from its zero crossings.
#include "mpm_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace tear {
namespace {
using testing::MpmSim;

using testing::basic_scene;
using testing::lattice_block;

constexpr double kPi = 3.14159265358979323846;

double measured_frequency(Model model, double fiber_scale) {
  const double E = 1e4, rho = 1, L = 1, dx = 1.0 / 128, x0 = 0.25;
  Scene s = basic_scene(2, dx, Vec3d(0, 0, 0), Vec3d(1.5, 0.5, 0), model, E, 0.0, rho,
                        fiber_scale);
  // Sticky clamp: every node at x <= x0 is held still.
  Collider clamp;
  clamp.type = ContactType::Sticky;
  clamp.shape.type = Shape::Type::Box;
  clamp.shape.dim = 2;
  clamp.shape.min = Vec3d(-1, -1, 0);
  clamp.shape.max = Vec3d(x0 + 1e-9, 2, 0);
  s.boundaries.push_back(clamp);
  const double c = wave_speed(s.materials[0].params);
  const double v0 = 1e-3 * c;
  auto vel = [&](const Vec<2>& x) {
    return Vec<2>(Real(v0 * std::sin(kPi * (x[0] - x0) / (2 * L))), 0);
  };
  Particles<2> p = lattice_block<2>(s, Vec<2>(Real(x0), Real(0.2)),
                                    Vec<2>(Real(x0 + L), Real(0.2 + 4 * dx)), 2, vel);
  MpmSim<2> sim(s, std::move(p));
  auto mean_v = [&] {
    double m = 0;
    for (size_t i = 0; i < sim.particles().size(); ++i) m += sim.particles().v[i][0];
    return m / sim.particles().size();
  };
  std::vector<double> crossings;
  double prev = mean_v(), t_prev = 0;
  const double t_end = 2.6 * 4 * L / c;  // a bit over 2.5 periods of the expected mode
  while (sim.time() < t_end) {
    sim.step(sim.estimate_dt());
    const double cur = mean_v();
    if ((prev > 0) != (cur > 0)) {
      crossings.push_back(t_prev + (sim.time() - t_prev) * prev / (prev - cur));
    }
    prev = cur, t_prev = sim.time();
  }
  EXPECT_GE(crossings.size(), 4u);
  if (crossings.size() < 2) return 0;
  const double half_period = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  return 1 / (2 * half_period);
}

double analytic_frequency(double E_eff, double rho, double L) {
  return std::sqrt(E_eff / rho) / (4 * L);
}

void report(double f, double f0) {
  std::printf("measured %.4f Hz, analytic %.4f Hz, ratio %.4f\n", f, f0, f / f0);
}

TEST(Vibration, QrAnisoBarMatchesAnalyticFrequency) {
  const double f = measured_frequency(Model::QrAniso, 0);
  const double f0 = analytic_frequency(1e4, 1, 1);
  report(f, f0);
  EXPECT_NEAR(f / f0, 1.0, 0.03) << "measured " << f << " Hz, expected " << f0 << " Hz";
}

TEST(Vibration, FixedCorotatedBarMatchesAnalyticFrequency) {
  const double f = measured_frequency(Model::FixedCorotated, 0);
  const double f0 = analytic_frequency(1e4, 1, 1);
  report(f, f0);
  EXPECT_NEAR(f / f0, 1.0, 0.03) << "measured " << f << " Hz, expected " << f0 << " Hz";
}

TEST(Vibration, FibersAlongTheBarRaiseTheFrequencyAsPredicted) {
  // nu = 0: mu = E / 2, kx = gamma mu, so E_eff = E (1 + gamma / 2).
  const double gamma = 2;
  const double f = measured_frequency(Model::QrAniso, gamma);
  const double f0 = analytic_frequency(1e4 * (1 + gamma / 2), 1, 1);
  report(f, f0);
  EXPECT_NEAR(f / f0, 1.0, 0.03) << "measured " << f << " Hz, expected " << f0 << " Hz";
}

}  // namespace
}  // namespace tear
