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


double measured_frequency(Model model, double fiber_scale) {
  const double E = 1e4, L = 1, dx = 1.0 / 128;
  MpmSim<2> sim = testing::clamped_bar(model, E, dx, fiber_scale);
  const double c = wave_speed(sim.settings().materials[0]);
  // A bit over 2.5 periods of the expected mode.
  const std::vector<double> crossings = testing::velocity_zero_crossings(
      sim, 2.6 * 4 * L / c, [](const MpmSim<2>& m) { return m.estimate_dt(); });
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
