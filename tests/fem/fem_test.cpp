// fem/: element forces and Hessians against differences of the energy, the patch test, a bar
// hanging under its own weight (rho g L^2 / 2E), its axial frequency (c / 4L), momentum and
// angular momentum of a spinning body, the implicit integrator's energy, same bits on any
// thread count, and the meshes netgen makes (volumes, determinism, checks).
#include "tear/driver/simulation.h"
#include "tear/exec/threads.h"
#include "tear/fem/fem.h"
#include "tear/io/mesh_frames.h"
#include "tear/materials/registry.h"
#include "tear/scene/scene.h"
#include "fem_test_util.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace tear {
namespace {

using test::structured_box;

MpmSettings settings_of(Model model, double E, double nu, double rho, int dim) {
  MpmSettings s;
  s.dx = 0.05;
  s.domain_min = Vec3d::Constant(-10);
  s.domain_max = Vec3d::Constant(10);
  if (dim == 2) s.domain_min.z() = s.domain_max.z() = 0;
  s.walls = ContactType::None;
  s.materials = {make_material(model, Real(E), Real(nu), Real(rho), model == Model::QrAniso ? 2 : 0,
                               model == Model::QrAniso ? 1 : 0)};
  return s;
}

template <int Dim>
FemState<Dim> state_of(const FemMesh& mesh, const MpmSettings& s, const Mat<Dim>& fiber) {
  FemState<Dim> st;
  append_fem_body<Dim>(
      mesh, s.materials, [&](const Vec3d&, size_t) { return ElementSetup<Dim>{0, fiber}; },
      Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), &st);
  return st;
}

template <int Dim>
Mat<Dim> rotation(double angle) {
  Mat<Dim> R = Mat<Dim>::Identity();
  if constexpr (Dim == 2) {
    R << Real(std::cos(angle)), Real(-std::sin(angle)), Real(std::sin(angle)), Real(std::cos(angle));
  } else {
    R = Eigen::AngleAxis<Real>(Real(angle), Vec<3>(1, 2, 3).normalized()).toRotationMatrix();
  }
  return R;
}

template <int Dim>
void check_derivatives(Model model) {
  SCOPED_TRACE(std::string(model_name(model)) + " " + std::to_string(Dim) + "D");
  const MpmSettings s = settings_of(model, 1e4, 0.3, 1000, Dim);
  const FemMesh mesh =
      structured_box(Dim, Vec3d::Zero(), Vec3d(0.2, 0.1, 0.1), {2, 1, 1});
  const FemState<Dim> st = state_of<Dim>(mesh, s, rotation<Dim>(0.4));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec<Dim>> x = st.nodes.x;
  for (Vec<Dim>& xi : x)
    for (int a = 0; a < Dim; ++a) xi[a] += Real(0.01 * u(rng));
  std::vector<Vec<Dim>> g;
  fem_elastic_gradient(s, st, x, &g);
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < Dim; ++a) {
      std::vector<Vec<Dim>> xp = x, xm = x;
      xp[i][a] += Real(h), xm[i][a] -= Real(h);
      const double fd = (fem_elastic_energy(s, st, xp) - fem_elastic_energy(s, st, xm)) / (2 * h);
      worst = std::max(worst, std::abs(fd - double(g[i][a])));
      scale = std::max(scale, std::abs(double(g[i][a])));
    }
  EXPECT_LT(worst, 1e-6 * scale) << "gradient against central differences of the energy";
  // Each element's Hessian against differences of its own corner forces: on one element
  // stretched 3 % (where the projection changes nothing: compressed, the rotations' eigenvalues
  // of the corotated models turn negative and are clipped).
  FemMesh single;
  single.dim = Dim;
  for (int k = 0; k <= Dim; ++k) single.nodes.push_back(mesh.nodes[size_t(mesh.elements[0][size_t(k)])]);
  single.elements.push_back({0, 1, 2, Dim == 3 ? 3 : -1});
  const FemState<Dim> one_st = state_of<Dim>(single, s, rotation<Dim>(0.4));
  std::vector<Vec<Dim>> y = one_st.nodes.x;
  for (Vec<Dim>& yi : y)
    for (int a = 0; a < Dim; ++a) yi[a] = Real(1.03) * yi[a] + Real(0.0005 * u(rng));
  const Eigen::MatrixXd H = fem_element_hessian(s, one_st, y, 0);
  double hworst = 0, hscale = H.cwiseAbs().maxCoeff();
  for (int j = 0; j < (Dim + 1) * Dim; ++j) {
    std::vector<Vec<Dim>> yp = y, ym = y, gp, gm;
    yp[size_t(j / Dim)][j % Dim] += Real(h);
    ym[size_t(j / Dim)][j % Dim] -= Real(h);
    fem_elastic_gradient(s, one_st, yp, &gp);
    fem_elastic_gradient(s, one_st, ym, &gm);
    for (int i = 0; i < (Dim + 1) * Dim; ++i) {
      const double fd = double(gp[size_t(i / Dim)][i % Dim] - gm[size_t(i / Dim)][i % Dim]) / (2 * h);
      hworst = std::max(hworst, std::abs(fd - H(i, j)));
    }
  }
  EXPECT_LT(hworst, 1e-5 * hscale) << "Hessian against central differences of the forces";
  EXPECT_GT(H.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff(), -1e-8 * hscale);
}

TEST(FemElements, ForcesAndHessiansMatchDifferencesOfTheEnergy) {
  for (Model m : {Model::FixedCorotated, Model::NeoHookean, Model::StvkHencky, Model::QrAniso}) {
    check_derivatives<2>(m);
    check_derivatives<3>(m);
  }
}

// Any uniform deformation x -> A x + b leaves no force on interior nodes (the patch test), for
// a linear and a nonlinear model, on netgen's unstructured meshes.
template <int Dim>
void patch_test(Model model) {
  const MpmSettings s = settings_of(model, 1e5, 0.3, 1000, Dim);
  Shape box;
  box.type = Shape::Type::Box;
  box.dim = Dim;
  box.min = Vec3d(0, 0, 0);
  box.max = Vec3d(0.4, 0.3, Dim == 3 ? 0.3 : 0);
  const FemMesh mesh = mesh_shape(box, Dim, 0.08);
  const FemState<Dim> st = state_of<Dim>(mesh, s, Mat<Dim>::Identity());
  Mat<Dim> A = Mat<Dim>::Identity();
  A(0, 0) = Real(1.1), A(0, 1) = Real(0.05), A(1, 0) = Real(-0.03), A(1, 1) = Real(0.95);
  std::vector<Vec<Dim>> x = st.nodes.x;
  for (Vec<Dim>& xi : x) xi = A * xi + Vec<Dim>::Constant(Real(0.2));
  std::vector<Vec<Dim>> g;
  fem_elastic_gradient(s, st, x, &g);
  std::vector<bool> boundary(x.size(), false);
  for (const std::array<int, 3>& f : st.faces)
    for (int k = 0; k < Dim; ++k) boundary[size_t(f[size_t(k)])] = true;
  double interior = 0, edge = 0;
  int inner = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (boundary[i]) {
      edge = std::max(edge, double(g[i].norm()));
    } else {
      interior = std::max(interior, double(g[i].norm()));
      ++inner;
    }
  }
  EXPECT_GT(inner, 3);
  EXPECT_GT(edge, 0);
  EXPECT_LT(interior, 1e-10 * edge) << inner << " interior nodes";
}

TEST(FemElements, PatchTestLeavesNoInteriorForce) {
  patch_test<2>(Model::FixedCorotated);
  patch_test<2>(Model::NeoHookean);
  patch_test<3>(Model::FixedCorotated);
  patch_test<3>(Model::QrAniso);
}

Scene scene_of(const std::string& text) { return load_scene_text(text, "fem_test.json"); }

// A bar of length L held at its top end hangs under its own weight: its bottom drops
// rho g L^2 / (2 E) (nu = 0: no lateral contraction to restrain at the grip). Backward Euler with
// long steps damps the motion away and leaves the static state.
TEST(FemDynamics, HangingBarStretchesByRhoGLSquaredOverTwoE) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    const std::string z = dim == 3 ? ", 0.45" : "";
    const std::string z2 = dim == 3 ? ", 0.55" : "";
    const Scene s = scene_of(R"({"dim": )" + std::to_string(dim) + R"(,
      "grid": {"dx": 0.05, "domain_min": [0, 0)" + (dim == 3 ? ", 0" : std::string()) +
                             R"(], "domain_max": [1, 1.5)" + (dim == 3 ? ", 1" : std::string()) +
                             R"(], "walls": "none"},
      "time": {"frame_dt": 0.5, "frames": 8, "max_dt": 0.05},
      "gravity": [0, -9.81)" + (dim == 3 ? ", 0" : std::string()) + R"(], "integrator": "implicit",
      "materials": {"steel": {"model": "fixed_corotated", "E": 1e6, "nu": 0, "rho": 1000}},
      "objects": [{"simulation": "fem", "mesh_size": 0.05, "material": "steel",
                   "shape": {"type": "box", "min": [0.45, 0.2)" + z + R"(], "max": [0.55, 1.2)" + z2 + R"(]}}],
      "boundaries": [{"type": "sticky", "shape": {"type": "box", "min": [0.3, 1.19)" +
                             (dim == 3 ? ", 0.3" : std::string()) + R"(], "max": [0.7, 1.3)" +
                             (dim == 3 ? ", 0.7" : std::string()) + R"(]}}]})");
    auto sim = make_simulation(s);
    const PointTable before = sim->frame_table();
    for (int f = 0; f < 8; ++f) sim->advance_frame();
    const PointTable& after = sim->frame_table();
    const std::vector<double>& y0 = before.column("y");
    const std::vector<double> y1 = after.column("y");
    double drop = 0;
    int bottom = 0;
    for (size_t i = 0; i < y0.size(); ++i)
      if (y0[i] < 0.2 + 1e-6) drop += y0[i] - y1[i], ++bottom;
    drop /= bottom;
    const double expected = 1000 * 9.81 * 1.0 * 1.0 / (2 * 1e6);
    EXPECT_NEAR(drop, expected, 0.03 * expected) << bottom << " nodes at the bottom";
    EXPECT_LT(sim->collect_stats().kinetic_energy, 1e-6);
  }
}

// A 2D bar of length 1 (40 x 2 cells unless told) clamped at x = 0 by a sticky box (added to s's colliders),
// its elements made with `setup`, moving with a small velocity that grows along it (mostly its
// first axial mode).
FemState<2> clamped_bar(MpmSettings* s, const ElementSetup<2>& setup = {}, int cells = 40,
                        int rows = 2) {
  const FemMesh mesh = structured_box(2, Vec3d::Zero(), Vec3d(1, 0.05, 0), {cells, rows, 1});
  FemState<2> st;
  append_fem_body<2>(mesh, s->materials, [&](const Vec3d&, size_t) { return setup; },
                     Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), &st);
  Collider grip;
  grip.type = ContactType::Sticky;
  grip.shape.type = Shape::Type::Box;
  grip.shape.dim = 2;
  grip.shape.min = Vec3d(-0.1, -0.1, 0);
  grip.shape.max = Vec3d(0.001, 0.2, 0);
  s->colliders = {grip};
  for (size_t i = 0; i < st.num_nodes(); ++i)
    st.nodes.v[i] = Vec<2>(Real(0.01 * std::sin(M_PI / 2 * st.nodes.x[i].x())), 0);
  return st;
}

// The period of the bar's free end's axial velocity (from its sign changes), stepping by
// `dt` (0: the explicit limit) until `t_end`.
double tip_period(const MpmSettings& s, FemState<2>* st, double dt, double t_end) {
  std::vector<size_t> tip;
  for (size_t i = 0; i < st->num_nodes(); ++i)
    if (st->nodes.x[i].x() > 1 - 1e-9) tip.push_back(i);
  const auto tip_v = [&] {
    double v = 0;
    for (size_t i : tip) v += double(st->nodes.v[i].x());
    return v;
  };
  std::vector<double> crossings;
  double prev = tip_v();
  while (st->time < t_end) {
    const double h = dt > 0 ? dt : fem_dt_limits(s, *st).dt();
    fem_step(s, st, h, nullptr);
    const double v = tip_v();
    if ((prev > 0) != (v > 0)) crossings.push_back(st->time - h * v / (v - prev));
    prev = v;
  }
  if (crossings.size() < 6) return 0;
  return (crossings[5] - crossings[1]) / 2;
}

// A bar fixed at one end vibrates along its axis at f = c / (4 L), c = sqrt(E / rho) (2D strip,
// nu = 0). Explicit steps; the period from the free end's velocity changing sign.
TEST(FemDynamics, BarVibratesAlongItsAxisAtCOverFourL) {
  MpmSettings s = settings_of(Model::FixedCorotated, 1e4, 0, 1, 2);
  s.cfl = 0.5;
  s.max_dt = 1;
  const double L = 1;
  FemState<2> st = clamped_bar(&s);
  const double period = tip_period(s, &st, 0, 0.2);
  const double expected = 4 * L / std::sqrt(1e4 / 1.0);
  EXPECT_NEAR(period, expected, 0.01 * expected);
}

// On a coarse bar (4 elements along) the first axial mode is the chain's discrete one, u_j =
// sin(j theta), theta = pi / 2N (the start's velocity), at omega h / c = 2 sin(theta / 2) with
// lumped mass (0.64 % under pi c / 2L) and sqrt(6 (1 - cos theta) / (2 + cos theta)) with
// consistent mass (0.64 % over): backward Euler with short steps (omega dt = 0.01) gives each
// within 0.15 %.
TEST(FemDynamics, ConsistentMassRaisesTheCoarseBarsFrequencyAsTheoryPredicts) {
  const double c = 100, N = 4, h = 1 / N, theta = M_PI / (2 * N);
  for (bool consistent : {false, true}) {
    SCOPED_TRACE(consistent ? "consistent" : "lumped");
    MpmSettings s = settings_of(Model::FixedCorotated, c * c, 0, 1, 2);
    s.integrator = Integrator::Implicit;
    s.newton.tolerance = 1e-10;
    ElementSetup<2> setup;
    setup.consistent_mass = consistent;
    FemState<2> st = clamped_bar(&s, setup, int(N), 1);
    const double omega = consistent
                             ? c / h * std::sqrt(6 * (1 - std::cos(theta)) / (2 + std::cos(theta)))
                             : c / h * 2 * std::sin(theta / 2);
    const double period = tip_period(s, &st, 0.01 / omega, 3.2 * 2 * M_PI / omega);
    EXPECT_NEAR(period, 2 * M_PI / omega, 1.5e-3 * 2 * M_PI / omega);
    const double exact = 4 / c;  // 4L / c
    if (consistent)
      EXPECT_LT(period, 0.995 * exact);
    else
      EXPECT_GT(period, 1.005 * exact);
  }
  // The explicit integrator takes lumped mass only.
  MpmSettings s = settings_of(Model::FixedCorotated, c * c, 0, 1, 2);
  ElementSetup<2> setup;
  setup.consistent_mass = true;
  FemState<2> st = clamped_bar(&s, setup, 4, 1);
  EXPECT_THROW(fem_step(s, &st, 1e-4, nullptr), std::invalid_argument);
}

// A block sliding on a floor with Coulomb friction mu slows at mu g: its centre of mass's speed
// after t is v0 - mu g t (explicit and implicit, 2D), and on a slip floor it keeps v0.
TEST(FemDynamics, BlockSlidingOnAFrictionFloorSlowsAtMuG) {
  const double v0 = 2, mu = 0.3, g = 9.81, t_end = 0.3;
  for (const Integrator integrator : {Integrator::Explicit, Integrator::Implicit})
    for (const double friction : {mu, 0.0}) {
      SCOPED_TRACE(std::string(integrator == Integrator::Explicit ? "explicit" : "implicit") +
                   " mu " + std::to_string(friction));
      MpmSettings s = settings_of(Model::FixedCorotated, 1e5, 0.3, 1000, 2);
      s.integrator = integrator;
      s.gravity = Vec3d(0, -g, 0);
      s.max_dt = 1e-3;
      const FemMesh mesh = structured_box(2, Vec3d(0, 0, 0), Vec3d(0.2, 0.1, 0), {4, 2, 1});
      FemState<2> st;
      append_fem_body<2>(
          mesh, s.materials, [&](const Vec3d&, size_t) { return ElementSetup<2>{}; },
          Vec3d(v0, 0, 0), Vec3d::Zero(), Vec3d::Zero(), &st);
      Collider floor;
      floor.type = ContactType::Separate;
      floor.friction = friction;
      floor.shape.type = Shape::Type::HalfSpace;
      floor.shape.dim = 2;
      floor.shape.point = Vec3d(0, 1e-4, 0);
      floor.shape.normal = Vec3d(0, 1, 0);
      s.colliders = {floor};
      while (st.time < t_end - 1e-12)
        fem_step(s, &st, std::min(fem_dt_limits(s, st).dt(), t_end - st.time), nullptr);
      const FemFigures f = measure_fem(s, st);
      const double v = f.momentum.x() / f.mass;
      EXPECT_NEAR(v, v0 - friction * g * t_end, 0.02 * v0);
      EXPECT_NEAR(f.momentum.y() / f.mass, 0, 0.02);  // resting on the floor
    }
}

// Rayleigh damping -(alpha M + beta K) v damps the bar's first axial mode (omega = pi c / 2L) at
// the rate zeta omega = alpha / 2 + beta omega^2 / 2: its energy falls by exp(-2 zeta omega t).
// Explicit steps (their dt shortened by the damping, fem_dt_limits).
TEST(FemDynamics, RayleighDampingDecaysTheAxialModeAtItsRate) {
  const double L = 1, c = 100, omega = M_PI * c / (2 * L);
  for (const auto& [alpha, beta] : {std::pair{4.0, 0.0}, std::pair{0.0, 5e-4}, std::pair{3.0, 3e-4}}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha) + " beta " + std::to_string(beta));
    MpmSettings s = settings_of(Model::FixedCorotated, c * c, 0, 1, 2);
    s.cfl = 0.5;
    s.max_dt = 1;
    ElementSetup<2> damped;
    damped.mass_damping = Real(alpha), damped.stiffness_damping = Real(beta);
    FemState<2> st = clamped_bar(&s, damped);
    const auto energy = [&] {
      const FemFigures f = measure_fem(s, st);
      return f.kinetic_energy + f.elastic_energy;
    };
    const double e0 = energy(), t_end = 0.1;
    const double undamped_dt = fem_dt_limits(s, clamped_bar(&s)).dt();
    EXPECT_LT(fem_dt_limits(s, st).dt(), beta > 0 ? 0.9 * undamped_dt : 1.01 * undamped_dt);
    while (st.time < t_end - 1e-12)
      fem_step(s, &st, std::min(fem_dt_limits(s, st).dt(), t_end - st.time), nullptr);
    const double zeta_omega = alpha / 2 + beta * omega * omega / 2;
    const double expected = std::exp(-2 * zeta_omega * t_end);
    // The energy oscillates a little between kinetic and elastic under damping: 5 %.
    EXPECT_NEAR(energy() / e0, expected, 0.05 * expected);
  }
}

// A rigid motion is not damped by beta K (K v = 0) and by alpha M at exactly the integrators'
// discrete rates: (1 - alpha dt)^n explicit, (1 + alpha dt)^-n implicit.
TEST(FemDynamics, RayleighDampingSlowsARigidMotionAtTheDiscreteRate) {
  for (const Integrator integrator : {Integrator::Explicit, Integrator::Implicit}) {
    MpmSettings s = settings_of(Model::NeoHookean, 1e4, 0.3, 1000, 3);
    s.integrator = integrator;
    const FemMesh mesh = structured_box(3, Vec3d::Zero(), Vec3d(0.3, 0.2, 0.1), {3, 2, 1});
    FemState<3> st;
    const double alpha = 2, beta = 0.01, dt = 1e-3;
    append_fem_body<3>(
        mesh, s.materials,
        [&](const Vec3d&, size_t) {
          ElementSetup<3> e;
          e.mass_damping = Real(alpha), e.stiffness_damping = Real(beta);
          return e;
        },
        Vec3d(0.5, -0.2, 0.1), Vec3d::Zero(), Vec3d::Zero(), &st);
    const Vec3d p0 = measure_fem(s, st).momentum;
    const int n = 50;
    FemSolveStats stats;
    for (int k = 0; k < n; ++k) fem_step(s, &st, dt, &stats);
    const double factor = integrator == Integrator::Explicit ? std::pow(1 - alpha * dt, n)
                                                             : std::pow(1 + alpha * dt, -n);
    EXPECT_LT((measure_fem(s, st).momentum - factor * p0).norm(), 1e-9 * p0.norm());
    EXPECT_LT(measure_fem(s, st).elastic_energy, 1e-12 * measure_fem(s, st).kinetic_energy);
    EXPECT_EQ(stats.unconverged, 0);
  }
}

// Explicit steps of a free, spinning, deformed body keep its momentum and angular momentum to
// round-off (internal forces sum to zero, and so do their moments: symplectic Euler then keeps
// sum m x^n x v exactly).
TEST(FemDynamics, SpinningBodyKeepsMomentumAndAngularMomentum) {
  MpmSettings s = settings_of(Model::NeoHookean, 1e4, 0.3, 1000, 3);
  const FemMesh mesh = structured_box(3, Vec3d::Zero(), Vec3d(0.3, 0.2, 0.1), {3, 2, 1});
  FemState<3> st;
  append_fem_body<3>(mesh, s.materials, [](const Vec3d&, size_t) { return ElementSetup<3>{}; },
                     Vec3d(0.5, 0, 0), Vec3d(1, 2, 3), Vec3d(0.15, 0.1, 0.05), &st);
  for (size_t i = 0; i < st.num_nodes(); ++i) st.nodes.x[i] *= Real(1.05);  // stressed
  const FemFigures a = measure_fem(s, st);
  for (int k = 0; k < 200; ++k) fem_step(s, &st, fem_dt_limits(s, st).dt(), nullptr);
  const FemFigures b = measure_fem(s, st);
  EXPECT_LT((a.momentum - b.momentum).norm(), 1e-12 * a.momentum.norm());
  EXPECT_LT((a.angular_momentum - b.angular_momentum).norm(), 1e-10 * a.angular_momentum.norm());
  EXPECT_GT(a.elastic_energy, 0);
}

// Backward Euler dissipates: without forcing, kinetic plus elastic energy never rises from a step
// to the next; and the result is the same bits on one thread and on two.
TEST(FemDynamics, ImplicitEnergyNeverRisesAndBitsDoNotDependOnThreads) {
  MpmSettings s = settings_of(Model::QrAniso, 1e4, 0.3, 1000, 3);
  s.integrator = Integrator::Implicit;
  s.max_dt = 0.01;
  const FemMesh mesh = structured_box(3, Vec3d::Zero(), Vec3d(0.3, 0.2, 0.1), {3, 2, 1});
  std::vector<Vec<3>> last;
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    FemState<3> st;
    append_fem_body<3>(mesh, s.materials,
                       [](const Vec3d&, size_t) { return ElementSetup<3>{0, rotation<3>(0.3)}; },
                       Vec3d::Zero(), Vec3d(0, 0, 4), Vec3d(0.15, 0.1, 0.05), &st);
    for (size_t i = 0; i < st.num_nodes(); ++i) st.nodes.x[i].x() *= Real(1.2);
    FemSolveStats stats;
    double energy = 1e300;
    for (int k = 0; k < 30; ++k) {
      const FemFigures f = measure_fem(s, st);
      const double e = f.kinetic_energy + f.elastic_energy;
      EXPECT_LE(e, energy * (1 + 1e-12)) << "step " << k;
      energy = e;
      fem_step(s, &st, s.max_dt, &stats);
    }
    EXPECT_EQ(stats.unconverged, 0);
    if (threads == 2) {
      EXPECT_EQ(0, std::memcmp(last.data(), st.nodes.x.data(), last.size() * sizeof(last[0])));
    }
    last = st.nodes.x;
  }
}

TEST(FemMeshes, NetgenMeshesHaveTheShapesVolumeAndAreTheSameEachTime) {
  Shape disk;
  disk.type = Shape::Type::Sphere;
  disk.dim = 2;
  disk.center = Vec3d(0.5, 0.5, 0);
  disk.radius = 0.3;
  const FemMesh a = mesh_shape(disk, 2, 0.05), b = mesh_shape(disk, 2, 0.05);
  check_fem_mesh(a, "disk");
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.elements, b.elements);
  EXPECT_NEAR(mesh_figures(a).volume, M_PI * 0.09, 0.01 * M_PI * 0.09);
  EXPECT_GT(mesh_figures(a).worst_quality, 0.5);
  Shape ball = disk;
  ball.dim = 3;
  ball.center.z() = 0.5;
  const FemMesh c = mesh_shape(ball, 3, 0.05);
  check_fem_mesh(c, "ball");
  EXPECT_NEAR(mesh_figures(c).volume, 4.0 / 3 * M_PI * 0.027, 0.03 * 4.0 / 3 * M_PI * 0.027);
  Shape box;
  box.type = Shape::Type::Box;
  box.min = Vec3d(0, 0, 0);
  box.max = Vec3d(0.5, 0.2, 0.1);
  box.transform.rotate = Eigen::AngleAxisd(0.3, Vec3d::UnitZ()).toRotationMatrix();
  const FemMesh d = mesh_shape(box, 3, 0.05);
  check_fem_mesh(d, "box");
  EXPECT_NEAR(mesh_figures(d).volume, 0.01, 1e-12);
  EXPECT_GT(mesh_figures(d).worst_quality, 0.2);
}

TEST(FemMeshes, BadMeshesAreRefusedNamingTheElement) {
  const FemMesh good = structured_box(3, Vec3d::Zero(), Vec3d(1, 1, 1), {2, 1, 1});
  EXPECT_NO_THROW(check_fem_mesh(good, "m"));
  const auto message = [](const FemMesh& m) {
    try {
      check_fem_mesh(m, "m.msh");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  FemMesh inverted = good;
  std::swap(inverted.elements[3][1], inverted.elements[3][2]);
  EXPECT_EQ(message(inverted).rfind("m.msh: element 3 is inverted", 0), 0u) << message(inverted);
  FemMesh flat = good;
  flat.nodes[size_t(flat.elements[0][3])] = flat.nodes[size_t(flat.elements[0][0])] * 0.5 +
                                            flat.nodes[size_t(flat.elements[0][1])] * 0.5;
  EXPECT_NE(message(flat).find("degenerate"), std::string::npos) << message(flat);
  FemMesh range = good;
  range.elements[2][0] = 99;
  EXPECT_NE(message(range).find("element 2 refers to node 99"), std::string::npos);
  FemMesh unused = good;
  unused.nodes.push_back(Vec3d(5, 5, 5));
  EXPECT_NE(message(unused).find("belongs to no element"), std::string::npos);
  FemMesh two = good;
  const int n = int(two.nodes.size());
  for (Vec3d x : good.nodes) two.nodes.push_back(x + Vec3d(3, 0, 0));
  for (std::array<int, 4> t : good.elements) {
    for (int& k : t) k += n;
    two.elements.push_back(t);
  }
  EXPECT_NE(message(two).find("not connected"), std::string::npos) << message(two);
  FemMesh third = good;
  third.nodes.push_back(Vec3d(0.3, 0.3, -0.5));
  const std::array<int, 3> f = {third.elements[0][0], third.elements[0][1], third.elements[0][2]};
  third.elements.push_back({f[0], f[2], f[1], n});
  third.elements.push_back({f[0], f[1], f[2], n});
  orient_elements(&third);
  EXPECT_NE(message(third).find("not a manifold"), std::string::npos) << message(third);
}

TEST(FemScene, MixedAndUnsupportedScenesAreRefused) {
  const std::string head = R"({"dim": 2, "grid": {"dx": 0.05, "domain_min": [0, 0], "domain_max": [1, 1]},
      "time": {"frame_dt": 0.04, "frames": 1},
      "materials": {"m": {"model": "fixed_corotated", "E": 1e4, "nu": 0.3, "rho": 1000}},
      "objects": [)";
  const std::string fem =
      R"({"simulation": "fem", "material": "m", "shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}})";
  const auto error = [&](const std::string& objects) {
    try {
      scene_of(head + objects + "]}");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error(fem), "accepted");
  EXPECT_NE(error(fem + R"(, {"material": "m", "shape": {"type": "box", "min": [0.5, 0.5], "max": [0.6, 0.6]}})")
                .find("objects[1].simulation: is \"mpm\" but objects[0] is \"fem\""),
            std::string::npos);
  EXPECT_NE(error(R"({"simulation": "fem", "mesh_size": -1, "material": "m", "shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}})")
                .find("objects[0].mesh_size: must be a positive length"),
            std::string::npos);
  EXPECT_NE(error(R"({"simulation": "fem", "material": "m", "shape": {"type": "tube", "center": [0.5, 0.5], "axis": [1, 0], "radius": 0.2, "inner_radius": 0.1, "height": 0.3}})")
                .find("objects[0].shape: an FEM body is meshed from a box, sphere, cylinder"),
            std::string::npos);
  EXPECT_NE(error(R"({"material": "m", "mesh_size": 0.1, "shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}})")
                .find("objects[0].mesh_size: is for \"simulation\": \"fem\" objects only"),
            std::string::npos);
  // Consistent mass: FEM bodies and the implicit integrator only.
  EXPECT_NE(error(R"({"simulation": "fem", "mass": "consistent", "material": "m", "shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}})")
                .find("objects[0].mass: \"consistent\" needs \"integrator\": \"implicit\""),
            std::string::npos);
  EXPECT_NE(error(R"({"material": "m", "mass": "lumped", "shape": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}})")
                .find("objects[0].mass: is for \"simulation\": \"fem\" objects only"),
            std::string::npos);
  // Rayleigh damping: FEM bodies only, non-negative.
  const auto damped = [&](const std::string& rayleigh, const std::string& objects) {
    std::string text = head;
    text.replace(text.find(R"("rho": 1000)"), 11, R"("rho": 1000, "rayleigh": )" + rayleigh);
    try {
      scene_of(text + objects + "]}");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(damped(R"({"alpha": 1, "beta": 1e-4})", fem), "accepted");
  EXPECT_NE(damped(R"({"alpha": -1})", fem).find("materials.m.rayleigh.alpha: must be"), std::string::npos)
      << damped(R"({"alpha": -1})", fem);
  EXPECT_NE(damped(R"({"gamma": 1})", fem).find("materials.m.rayleigh"), std::string::npos);
  const std::string mpm = R"({"material": "m", "shape": {"type": "box", "min": [0.5, 0.5], "max": [0.6, 0.6]}})";
  EXPECT_NE(damped(R"({"beta": 1e-4})", mpm)
                .find("objects[0].material: material \"m\" has Rayleigh damping (rayleigh), which only FEM bodies take"),
            std::string::npos)
      << damped(R"({"beta": 1e-4})", mpm);
}

// The volume's element figures: a uniform stretch by s gives every element J = s^d, the same
// energy density (the model's Psi(s I)), and no von Mises stress (the stress is hydrostatic); a
// uniaxial stretch gives von Mises |sigma_xx - sigma_yy| (3D: the lateral stresses are equal).
TEST(FemElements, ElementFiguresOfUniformStretches) {
  MpmSettings s = settings_of(Model::NeoHookean, 1e4, 0.3, 1000, 3);
  const FemMesh mesh = structured_box(3, Vec3d::Zero(), Vec3d(0.3, 0.2, 0.1), {3, 2, 1});
  FemState<3> st = state_of<3>(mesh, s, Mat<3>::Identity());
  for (Vec<3>& x : st.nodes.x) x *= Real(1.02);
  FemElementFigures f = fem_element_figures(s, st);
  const double psi = double(energy_density<3>(s.materials[0], Real(1.02) * Mat<3>::Identity(),
                                              Mat<3>::Identity()));
  for (size_t e = 0; e < st.elements.size(); ++e) {
    EXPECT_NEAR(f.J[e], std::pow(1.02, 3), 1e-12);
    EXPECT_NEAR(f.energy[e], psi, 1e-9 * psi);
    EXPECT_LT(f.von_mises[e], 1e-9 * psi);
    EXPECT_NEAR(f.fiber[e].x(), 1, 1e-12);
  }
  Mat<3> F = Mat<3>::Identity();
  F(0, 0) = Real(1.05);
  for (Vec<3>& x : st.nodes.x) x = F * x / Real(1.02);
  f = fem_element_figures(s, st);
  const Mat<3> sigma =
      first_piola<3>(s.materials[0], F, Mat<3>::Identity()) * F.transpose() / F.determinant();
  for (size_t e = 0; e < st.elements.size(); ++e)
    EXPECT_NEAR(f.von_mises[e], double(sigma(0, 0) - sigma(1, 1)), 1e-9 * double(sigma(0, 0)));
}

// A checkpoint taken mid-run and resumed in a new simulation ends in the same bytes as the run
// that never stopped; frames carry the mesh.
TEST(FemScene, ResumedRunEndsInTheSameCheckpoint) {
  const Scene s = scene_of(R"({"dim": 3,
      "grid": {"dx": 0.05, "domain_min": [0, 0, 0], "domain_max": [1, 1, 1], "walls": "slip"},
      "time": {"frame_dt": 0.02, "frames": 6, "max_dt": 0.005},
      "gravity": [0, -9.81, 0], "integrator": "implicit",
      "materials": {"jelly": {"model": "neo_hookean", "E": 2e4, "nu": 0.3, "rho": 1000}},
      "objects": [{"simulation": "fem", "mesh_size": 0.1, "material": "jelly",
                   "angular_velocity": [0, 0, 3],
                   "shape": {"type": "sphere", "center": [0.5, 0.35, 0.5], "radius": 0.15}}]})");
  std::string mid;
  const auto whole = test::expect_resumes_identically(s, 6, &mid);
  const std::vector<MeshPart> parts = whole->frame_meshes();
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].name, "fem");
  EXPECT_GT(parts[0].elements.size(), 50u);
  // The volume: every tetrahedron with its figures, written as VTU (tetrahedra) only.
  EXPECT_EQ(parts[1].name, "volume");
  EXPECT_EQ(parts[1].corners, 4);
  EXPECT_EQ(parts[1].elements.size(), parts[1].element_columns.count);
  for (const char* column : {"id", "material", "energy", "von_mises", "J", "fx", "fy", "fz"})
    EXPECT_TRUE(parts[1].element_columns.has(column)) << column;
  EXPECT_EQ(mesh_part_formats_of(parts[1], {"ply", "obj"}), std::vector<std::string>{"vtu"});
  EXPECT_THROW(encode_mesh_part(parts[1], "ply"), std::runtime_error);
  const std::string vtu = encode_mesh_part(parts[1], "vtu");
  EXPECT_NE(vtu.find("NumberOfCells=\"" + std::to_string(parts[1].elements.size()) + "\""),
            std::string::npos);
  EXPECT_NE(vtu.find("Name=\"types\" format=\"ascii\">10 10 "), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"fiber\" NumberOfComponents=\"3\""), std::string::npos);
  // The ball fell onto the slip floor (walls act kWallNodes cells inside the domain) and stays
  // above it.
  const std::vector<double> y = whole->frame_table().column("y");
  EXPECT_GT(*std::min_element(y.begin(), y.end()), 3 * 0.05 - 0.01);
  EXPECT_LT(*std::min_element(y.begin(), y.end()), 0.2);
  std::string bad = mid;
  bad[bad.size() / 2] ^= 1;
  EXPECT_THROW(make_simulation(s)->decode_checkpoint(bad), std::runtime_error);
}


// The distance from the nodes `x` to the rest shape `rest` moved rigidly to fit them best (Kabsch:
// the rotation from the SVD of their covariance), as the RMS over the nodes.
double distance_from_rigid(const std::vector<double>& rx, const std::vector<double>& ry,
                           const std::vector<double>& rz, const std::vector<double>& x,
                           const std::vector<double>& y, const std::vector<double>& z) {
  const size_t n = rx.size();
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) a += Eigen::Vector3d(rx[i], ry[i], rz[i]), b += Eigen::Vector3d(x[i], y[i], z[i]);
  a /= double(n), b /= double(n);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i)
    H += (Eigen::Vector3d(rx[i], ry[i], rz[i]) - a) * (Eigen::Vector3d(x[i], y[i], z[i]) - b).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  double sum = 0;
  for (size_t i = 0; i < n; ++i)
    sum += (R * (Eigen::Vector3d(rx[i], ry[i], rz[i]) - a) + b - Eigen::Vector3d(x[i], y[i], z[i])).squaredNorm();
  return std::sqrt(sum / double(n));
}

// AnisoMPM Fig. 19: under qr_aniso an FEM body whose nodes start at random points of its box
// (19a), isotropic and fibered, or all within mesh_size / 1000 of one point (19b), fibered,
// recovers its rest shape up to a rigid motion (backward Euler), in 2D and 3D. Its elastic energy
// falls by five orders or more; it may keep a slow spin: backward Euler does not keep angular
// momentum (it adds dt sum m v^n+1 x v^n a step, and the recovery is violent), so "at rest" is
// not asserted. The isotropic model from one point is not: in 3D F = 0 is a local minimum of its
// energy (QrAnisoAtZero below); in 2D it leaves F = 0 but settles elsewhere (288 J -> 89 J,
// docs/fem.md).
TEST(FemInversion, QrAnisoRecoversTheRestShapeFromRandomAndOnePointStarts) {
  for (int dim : {2, 3})
    for (const char* start : {"random", "point"})
      for (bool fibered : {false, true}) {
        if (!fibered && std::string(start) == "point") continue;  // QrAnisoAtZero
        const std::string fibers = fibered ? (dim == 3 ? "[4, 1]" : "[4]") : (dim == 3 ? "[0, 0]" : "[0]");
        SCOPED_TRACE(std::to_string(dim) + "D " + start + " fiber_scale " + fibers);
        const std::string box = dim == 3 ? R"({"type": "box", "min": [0.35, 0.4, 0.4], "max": [0.65, 0.6, 0.6]})"
                                         : R"({"type": "box", "min": [0.35, 0.4], "max": [0.65, 0.6]})";
        const std::string a1 = dim == 3 ? "[1, 1, 0]" : "[1, 1]";
        const std::string body = R"({"simulation": "fem", "mesh_size": 0.1, "material": "m", "shape": )" + box;
        const std::string fem = body + R"(, "initial_nodes": ")" + start +
                                R"(", "fibers": {"type": "constant", "a1": )" + a1 + "}}";
        const std::string lo = dim == 3 ? "[-2, -2, -2]" : "[-2, -2]", hi = dim == 3 ? "[3, 3, 3]" : "[3, 3]";
        const std::string head = R"({"dim": )" + std::to_string(dim) + R"(,
            "grid": {"dx": 0.05, "domain_min": )" + lo + R"(, "domain_max": )" + hi + R"(, "walls": "none"},
            "time": {"frame_dt": 0.1, "frames": 20, "max_dt": 0.01}, "integrator": "implicit",
            "materials": {"m": {"model": "qr_aniso", "E": 1e4, "nu": 0.3, "rho": 1000,
                                "fiber_scale": )" + fibers + R"(}},
            "objects": [)";
        auto sim = make_simulation(scene_of(head + fem + "]}"));
        const PointTable r = make_simulation(scene_of(head + body + "}]}"))->frame_table();
        const auto column_z = [&](const PointTable& t) {
          return t.has("z") ? t.column("z") : std::vector<double>(t.count, 0.0);
        };
        const PointTable s0 = sim->frame_table();
        const double before = distance_from_rigid(r.column("x"), r.column("y"), column_z(r),
                                                  s0.column("x"), s0.column("y"), column_z(s0));
        const double energy = sim->collect_stats().elastic_energy;
        long unconverged = 0;
        for (int f = 0; f < 20; ++f) {
          sim->advance_frame();
          unconverged += sim->collect_stats().newton_unconverged;
        }
        const PointTable& s1 = sim->frame_table();
        const double after = distance_from_rigid(r.column("x"), r.column("y"), column_z(r),
                                                 s1.column("x"), s1.column("y"), column_z(s1));
        const FrameStats st = sim->collect_stats();
        std::printf("%dD %s %s: RMS %.3g -> %.3g, elastic %.3g -> %.3g J, unconverged %ld\n", dim,
                    start, fibers.c_str(), before, after, energy, st.elastic_energy, unconverged);
        EXPECT_GT(before, 0.05);
        EXPECT_LE(unconverged, 2);
        EXPECT_LT(after, 1e-3) << "RMS distance from the rest shape, started at " << before;
        EXPECT_LT(st.elastic_energy, 1e-5 * energy) << "from " << energy;
        if (dim == 3 && std::string(start) == "random" && !fibered) {
          // The same start in neo-Hookean is refused: log J is undefined for inverted elements.
          std::string text = head + fem + "]}";
          text.replace(text.find("qr_aniso"), 8, "neo_hookean");
          try {
            make_simulation(scene_of(text));
            ADD_FAILURE() << "an inverted neo-Hookean start was accepted";
          } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("starts inverted or flat (initial_nodes \"random\"), "
                                                 "where neo_hookean is undefined"),
                      std::string::npos)
                << e.what();
          }
        }
      }
}

// Why the isotropic model stays at a point in 3D: at F = 0 its energy mu/2 (|F|^2 - 3) - mu (J - 1)
// + lambda/2 (J - 1)^2 has the gradient 0 (cof F = 0) and the Hessian mu I (J is cubic in F), a
// strict local minimum; in 2D J is quadratic and the Hessian mu I - (mu + lambda) d2J has a
// negative direction (a saddle), and a fiber's term kx/2 (|F a1| - 1)^2 falls along F a1 at once
// (a cone, -kx |F a1|) in both: the paper's argument for Fig. 19b.
TEST(FemInversion, QrAnisoAtZero) {
  const MaterialParams iso = make_material(Model::QrAniso, 1e4, 0.3, 1000, 0, 0);
  const MaterialParams fibered = make_material(Model::QrAniso, 1e4, 0.3, 1000, 4, 1);
  const double eps = 1e-3;
  uint64_t seed = 7;
  const auto next = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return double(seed >> 11) * 0x1.0p-53 * 2 - 1;
  };
  const double psi3 = double(energy_density<3>(iso, Mat<3>::Zero(), Mat<3>::Identity()));
  for (int k = 0; k < 200; ++k) {
    Mat<3> G;
    for (int i = 0; i < 9; ++i) G.data()[i] = Real(next());
    G /= G.norm();
    EXPECT_GT(double(energy_density<3>(iso, Real(eps) * G, Mat<3>::Identity())), psi3);
  }
  EXPECT_LT(first_piola<3>(iso, Mat<3>::Zero(), Mat<3>::Identity()).norm(), 1e-12);
  // 2D: along a rotation (F = s I) the isotropic energy falls.
  const double psi2 = double(energy_density<2>(iso, Mat<2>::Zero(), Mat<2>::Identity()));
  EXPECT_LT(double(energy_density<2>(iso, Real(eps) * Mat<2>::Identity(), Mat<2>::Identity())), psi2);
  // Fibered, 3D: along F = e a1^T (here a1 = e1) the energy falls at first order.
  Mat<3> along = Mat<3>::Zero();
  along(1, 0) = 1;
  const double f0 = double(energy_density<3>(fibered, Mat<3>::Zero(), Mat<3>::Identity()));
  const double f1 = double(energy_density<3>(fibered, Real(eps) * along, Mat<3>::Identity()));
  EXPECT_NEAR((f0 - f1) / eps, double(fibered.kx), 0.01 * double(fibered.kx));
}

}  // namespace
}  // namespace tear
