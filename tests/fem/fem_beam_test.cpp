// A cantilever of linear elements against beam theory: its tip deflection under its own weight
// (Timoshenko: q L^4 / 8EI + q L^2 / 2 kappa G A) converging from below under refinement (linear
// triangles and tetrahedra lock in bending: too stiff on coarse meshes), and its first bending
// frequency (1.8751^2 sqrt(EI / rho A L^4)) converging from above.
#include "tear/fem/fem.h"
#include "tear/materials/registry.h"
#include "fem_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace tear {
namespace {

using test::structured_box;

constexpr double kL = 1, kH = 0.1, kE = 1e9, kRho = 1000, kG = 9.81;

// A beam [0, L] x [0, H] (x [0, H] in 3D), n[0] x n[1] (x n[2]) cells, nu = 0 (no lateral
// stress at the clamp), clamped at x = 0 by a sticky box.
template <int Dim>
FemState<Dim> cantilever(MpmSettings* s, const std::array<int, 3>& n) {
  s->dx = kH / n[1];
  s->domain_min = Vec3d::Constant(-10);
  s->domain_max = Vec3d::Constant(10);
  if (Dim == 2) s->domain_min.z() = s->domain_max.z() = 0;
  s->walls = ContactType::None;
  s->materials = {make_material(Model::FixedCorotated, Real(kE), 0, Real(kRho), 0, 0)};
  const FemMesh mesh = structured_box(Dim, Vec3d::Zero(), Vec3d(kL, kH, kH), n);
  FemState<Dim> st;
  append_fem_body<Dim>(mesh, s->materials, [](const Vec3d&, size_t) { return ElementSetup<Dim>{}; },
                       Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), &st);
  Collider grip;
  grip.type = ContactType::Sticky;
  grip.shape.type = Shape::Type::Box;
  grip.shape.dim = Dim;
  grip.shape.min = Vec3d(-0.1, -0.1, Dim == 3 ? -0.1 : 0);
  grip.shape.max = Vec3d(1e-3 * kL / n[0], 0.2, Dim == 3 ? 0.2 : 0);
  s->colliders = {grip};
  return st;
}

template <int Dim>
std::vector<size_t> tip_nodes(const FemState<Dim>& st) {
  std::vector<size_t> tip;
  for (size_t i = 0; i < st.num_nodes(); ++i)
    if (st.nodes.x[i].x() > kL - 1e-9) tip.push_back(i);
  return tip;
}

// The beam settled under gravity: backward Euler with steps of many periods (omega dt = 200)
// settles into the static equilibrium in a few. `tip` gets the nodes at x = L and `rest` their heights before.
template <int Dim>
FemState<Dim> settled(const std::array<int, 3>& n, MpmSettings* s, std::vector<size_t>* tip,
                      std::vector<double>* rest) {
  FemState<Dim> st = cantilever<Dim>(s, n);
  s->gravity = Vec3d(0, -kG, 0);
  s->integrator = Integrator::Implicit;
  s->newton.tolerance = 1e-10;
  s->newton.max_iterations = 50;
  *tip = tip_nodes(st);
  for (size_t i : *tip) rest->push_back(double(st.nodes.x[i].y()));
  for (int k = 0; k < 3; ++k) fem_step(*s, &st, 2.0, nullptr);
  return st;
}

// The tip nodes' mean height below `rest`.
template <int Dim>
double tip_deflection(const FemState<Dim>& st, const std::vector<size_t>& tip,
                      const std::vector<double>& rest) {
  double d = 0;
  for (size_t k = 0; k < tip.size(); ++k) d += rest[k] - double(st.nodes.x[tip[k]].y());
  return d / double(tip.size());
}

template <int Dim>
double static_tip_deflection(const std::array<int, 3>& n) {
  MpmSettings s;
  std::vector<size_t> tip;
  std::vector<double> rest;
  const FemState<Dim> st = settled<Dim>(n, &s, &tip, &rest);
  return tip_deflection(st, tip, rest);
}

// Timoshenko's deflection of the cantilever under its weight q = rho g A: bending q L^4 / 8EI
// and shear q L^2 / (2 kappa G A), kappa = 5/6 (a rectangle, nu = 0), G = E / 2.
double timoshenko_deflection(int dim) {
  const double A = dim == 3 ? kH * kH : kH, I = (dim == 3 ? kH : 1.0) * kH * kH * kH / 12;
  const double q = kRho * kG * A;
  return q * std::pow(kL, 4) / (8 * kE * I) + q * kL * kL / (2 * (5.0 / 6) * (kE / 2) * A);
}

// Linear triangles lock: 54 % of the deflection with 2 elements through the depth, 82 % with 4,
// 95 % with 8; the error falls by half and then by 3.5 per halving (towards second order).
TEST(FemBeams, CantileverDeflectionConvergesToTimoshenkosFromBelow2D) {
  const double want = timoshenko_deflection(2);
  double previous_error = 1;
  for (int k : {2, 4, 8}) {
    const double d = static_tip_deflection<2>({10 * k, k, 1});
    const double error = 1 - d / want;
    std::printf("2D %d x %d cells: tip %.6g m, Timoshenko %.6g m, ratio %.4f\n", 10 * k, k, d,
                want, d / want);
    EXPECT_GT(error, 0) << "linear triangles are stiffer than the beam";
    EXPECT_LT(error, 0.5 * previous_error);
    previous_error = error;
  }
  EXPECT_LT(previous_error, 0.06);
}

// Tetrahedra (6 to a cube) lock as much: 55 % and 82 % with 2 and 4 elements through the depth.
TEST(FemBeams, CantileverDeflectionConvergesToTimoshenkosFromBelow3D) {
  const double want = timoshenko_deflection(3);
  double previous_error = 1;
  for (int k : {2, 4}) {
    const double d = static_tip_deflection<3>({10 * k, k, k});
    const double error = 1 - d / want;
    std::printf("3D %d x %d x %d cells: tip %.6g m, Timoshenko %.6g m, ratio %.4f\n", 10 * k, k,
                k, d, want, d / want);
    EXPECT_GT(error, 0);
    EXPECT_LT(error, 0.5 * previous_error);
    previous_error = error;
  }
}

// The first bending mode, released from the static deflection at rest (mostly mode 1) without
// gravity and stepped explicitly: its period from the tip's deflection changing sign, against
// 2 pi / omega_1, omega_1 = 1.8751^2 sqrt(EI / (rho A L^4)) (Euler-Bernoulli; shear lowers it by
// a few tenths of a percent at L / H = 10). Locking makes the coarse mesh's mode too fast (the
// period 74 % of the beam's with 2 elements through the depth, 91 % with 4: the square roots of
// the deflection ratios); refinement brings it down towards the beam's.
TEST(FemBeams, CantileverFirstBendingFrequencyConvergesFromAbove2D) {
  const double I = kH * kH * kH / 12, A = kH;
  const double omega = 1.8751 * 1.8751 * std::sqrt(kE * I / (kRho * A * std::pow(kL, 4)));
  const double want = 2 * M_PI / omega;
  double previous = 0;
  for (int k : {2, 4}) {
    MpmSettings s;
    std::vector<size_t> tip;
    std::vector<double> rest;
    FemState<2> st = settled<2>({10 * k, k, 1}, &s, &tip, &rest);
    s.gravity = Vec3d::Zero();
    s.integrator = Integrator::Explicit;
    s.cfl = 0.5;
    s.max_dt = 1;
    for (Vec<2>& v : st.nodes.v) v.setZero();
    std::vector<double> crossings;
    double prev = tip_deflection(st, tip, rest);
    const double t0 = st.time;
    while (crossings.size() < 5 && st.time < t0 + 10 * want) {
      const double dt = fem_dt_limits(s, st).dt();
      fem_step(s, &st, dt, nullptr);
      const double d = tip_deflection(st, tip, rest);
      if ((prev > 0) != (d > 0)) crossings.push_back(st.time - dt * d / (d - prev));
      prev = d;
    }
    ASSERT_EQ(crossings.size(), 5u);
    const double period = (crossings[4] - crossings[0]) / 2;
    std::printf("2D %d x %d cells: bending period %.6g s, Euler-Bernoulli %.6g s, ratio %.4f\n",
                10 * k, k, period, want, period / want);
    EXPECT_LT(period, want) << "locking makes the mode too fast";
    if (previous > 0) {
      EXPECT_GT(period, previous);
    }
    previous = period;
  }
  EXPECT_GT(previous, 0.9 * want);
}

// The study (ctest -L study): finer meshes, where the deflection keeps closing on Timoshenko's.
TEST(FemBeamStudy, CantileverDeflectionOnFinerMeshes) {
  const double want2 = timoshenko_deflection(2), want3 = timoshenko_deflection(3);
  for (int k : {16, 32}) {
    const double d = static_tip_deflection<2>({10 * k, k, 1});
    std::printf("2D %d x %d cells: tip %.6g m, Timoshenko %.6g m, ratio %.4f\n", 10 * k, k, d,
                want2, d / want2);
    EXPECT_LT(d, want2 * 1.001);
    EXPECT_GT(d, want2 * (k == 16 ? 0.97 : 0.99));
  }
  const double d = static_tip_deflection<3>({80, 8, 8});
  std::printf("3D 80 x 8 x 8 cells: tip %.6g m, Timoshenko %.6g m, ratio %.4f\n", d, want3,
              d / want3);
  EXPECT_GT(d, want3 * 0.9);
}

}  // namespace
}  // namespace tear
