// Directional inextensibility (mpm/inextensibility.h): the constraint rows against the fiber
// stretch rate of affine motions, B^T as B's transpose, momentum kept by the projection, the
// residual after the solve, hanging bars that do not stretch (explicit and implicit), the
// relaxed constraint tending to the hard one, bending not locked, cracks that open.
#include "mpm_test_util.h"
#include "tear/exec/threads.h"
#include "tear/io/field_io.h"
#include "tear/mpm/inextensibility.h"
#include "tear/mpm/phases.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tear {
namespace {
using testing::basic_scene;
using testing::lattice_block;
using testing::MpmSim;
using testing::sticky_box;

template <int Dim>
Mat<Dim> fiber_frame(Real angle) {
  Mat<Dim> D = Mat<Dim>::Identity();
  D(0, 0) = std::cos(angle), D(0, 1) = -std::sin(angle);
  D(1, 0) = std::sin(angle), D(1, 1) = std::cos(angle);
  return D;
}

// Runs the phases before the projection (sort, P2G, grid update) on sim's state.
template <int Dim>
void prepare_grid(MpmSim<Dim>& sim, double dt) {
  sort_particles(&sim.state());
  p2g(sim.settings(), &sim.state(), Real(dt));
  grid_update(sim.settings(), &sim.state(), Real(dt));
}

// A block of inextensible material, sampled at random (jittered lattice), fibers at `angle`,
// F = I: its grid after P2G and the grid update.
template <int Dim>
MpmSim<Dim> fibered_block(Real angle, std::vector<Collider> boundaries = {}) {
  Vec3d hi(1, 1, Dim == 3 ? 1 : 0);
  Scene s = basic_scene(Dim, Dim == 2 ? 0.05 : 0.1, Vec3d::Zero(), hi, Model::QrAniso, 1000, 0.3,
                        1, 0);
  s.materials[0].inextensibility.enabled = true;
  s.boundaries = std::move(boundaries);
  Particles<Dim> p = lattice_block<Dim>(s, Vec<Dim>::Constant(Real(0.3)),
                                        Vec<Dim>::Constant(Real(0.7)), 2,
                                        [](const Vec<Dim>& x) {
                                          Vec<Dim> v = Vec<Dim>::Zero();
                                          v[0] = Real(std::sin(3 * x[1]));
                                          v[1] = Real(0.5 * x[0] * x[0]);
                                          return v;
                                        });
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (size_t i = 0; i < p.size(); ++i) {
    for (int d = 0; d < Dim; ++d) p.x[i][d] += Real(u(rng) * s.dx / 2);
    p.fiber[i] = fiber_frame<Dim>(angle);
  }
  return MpmSim<Dim>(s, std::move(p));
}

// Affine grid velocities v_i = G x_i: MLS reproduces them, so every particle's velocity
// gradient is G and its fiber stretch rate a^T G a; with F = I the rows read that rate times
// their volumes.
template <int Dim>
void expect_rows_measure_the_fiber_stretch_rate() {
  for (const Real angle : {Real(0), Real(0.7), Real(2.2)}) {
    MpmSim<Dim> sim = fibered_block<Dim>(angle);
    const double dt = 1e-3;
    prepare_grid(sim, dt);
    const FiberConstraints<Dim> fc(sim.settings(), sim.state(), Real(dt));
    ASSERT_GT(fc.rows(), 0u);
    const Vec<Dim> a = fiber_frame<Dim>(angle).col(0);
    Mat<Dim> G = Mat<Dim>::Zero();
    G(0, 1) = 0.8, G(1, 0) = -0.3, G(0, 0) = 0.4;
    if (Dim == 3) G(2, 2) = 0.6, G(0, 2) = -0.2;
    std::vector<Vec<Dim>> v(sim.grid().num_active_nodes());
    for (size_t n = 0; n < v.size(); ++n) v[n] = G * sim.grid().node_position(int(n));
    const double rate = a.dot(G * a);
    EXPECT_NEAR(fc.strain_error(v), std::abs(rate) * dt, 1e-9 * dt) << "angle " << angle;
    // A rotation, and a shear across the fiber, do not stretch it.
    const Vec<Dim> b = fiber_frame<Dim>(angle).col(1);
    for (const Mat<Dim>& H : {Mat<Dim>(a * b.transpose() - b * a.transpose()),
                               Mat<Dim>(b * a.transpose() + b * b.transpose())}) {
      for (size_t n = 0; n < v.size(); ++n) v[n] = H * sim.grid().node_position(int(n));
      EXPECT_LT(fc.strain_error(v), 1e-12) << "angle " << angle;
    }
  }
}

TEST(Inextensibility, RowsMeasureTheFiberStretchRateOfAffineMotions2D) {
  expect_rows_measure_the_fiber_stretch_rate<2>();
}
TEST(Inextensibility, RowsMeasureTheFiberStretchRateOfAffineMotions3D) {
  expect_rows_measure_the_fiber_stretch_rate<3>();
}

// <B v, mu> = <v, B^T mu> for random v and mu; the projection leaves the constraint below its
// tolerance and, without boundaries, the grid's linear and angular momentum unchanged.
template <int Dim>
void expect_projection_keeps_momentum(InextensibilityPreconditioner pc) {
  MpmSim<Dim> sim = fibered_block<Dim>(Real(0.5));
  const double dt = 1e-3;
  prepare_grid(sim, dt);
  const FiberConstraints<Dim> fc(sim.settings(), sim.state(), Real(dt));
  const SparseGrid<Dim>& grid = sim.grid();
  const size_t nn = grid.num_active_nodes();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec<Dim>> v(nn), bt;
  for (auto& vi : v)
    for (int d = 0; d < Dim; ++d) vi[d] = Real(u(rng));
  std::vector<Real> mu(fc.rows()), c0, c1;
  for (auto& m : mu) m = Real(u(rng));
  std::vector<Vec<Dim>> zero(nn, Vec<Dim>::Zero());
  fc.constraint(zero, &c0);  // -r
  fc.constraint(v, &c1);
  fc.transpose(mu, &bt);
  double lhs = 0, rhs = 0;
  for (size_t z = 0; z < mu.size(); ++z) lhs += double(c1[z] - c0[z]) * mu[z];
  for (size_t n = 0; n < nn; ++n) rhs += double(v[n].dot(bt[n]));
  EXPECT_NEAR(lhs, rhs, 1e-10 * std::abs(rhs));

  auto momenta = [&](const std::vector<Vec<Dim>>& vel) {
    Vec3d p = Vec3d::Zero(), l = Vec3d::Zero();
    for (size_t n = 0; n < nn; ++n) {
      Vec3d x = Vec3d::Zero(), w = Vec3d::Zero();
      x.head<Dim>() = grid.node_position(int(n)).template cast<double>();
      w.head<Dim>() = (grid.mass[n] * vel[n]).template cast<double>();
      p += w;
      l += x.cross(w);
    }
    return std::make_pair(p, l);
  };
  std::vector<Vec<Dim>> vel = grid.velocity;
  const auto [p0, l0] = momenta(vel);
  const double before = fc.strain_error(vel);
  InextensibilitySettings solve;
  solve.tolerance = 1e-6;
  solve.preconditioner = pc;
  const PcgResult r = fc.project(&vel, solve);
  const auto [p1, l1] = momenta(vel);
  const double after = fc.strain_error(vel);
  std::printf("%dD projection (%s): strain error per step %.3g -> %.3g in %d CG iterations\n",
              Dim, pc == InextensibilityPreconditioner::Jacobi ? "Jacobi" : "Cholesky", before,
              after, r.iterations);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(before, 1e-4);
  EXPECT_LT(after, 1e-5 * before);  // a max norm; CG's tolerance is on the 2-norm
  EXPECT_LT((p1 - p0).norm(), 1e-10 * p0.norm());
  EXPECT_LT((l1 - l0).norm(), 1e-10 * l0.norm());
}

TEST(Inextensibility, ProjectionMeetsItsToleranceAndKeepsMomentum2D) {
  expect_projection_keeps_momentum<2>(InextensibilityPreconditioner::Cholesky);
  expect_projection_keeps_momentum<2>(InextensibilityPreconditioner::Jacobi);
}
TEST(Inextensibility, ProjectionMeetsItsToleranceAndKeepsMomentum3D) {
  expect_projection_keeps_momentum<3>(InextensibilityPreconditioner::Cholesky);
  expect_projection_keeps_momentum<3>(InextensibilityPreconditioner::Jacobi);
}

// The assembled Schur complement is the operator CG applies: S mu = B m^-1 B^T mu for random
// mu, in 2D and 3D (no walls: P = I).
template <int Dim>
void expect_schur_matrix_matches_the_operator() {
  MpmSim<Dim> sim = fibered_block<Dim>(Real(0.9));
  const double dt = 1e-3;
  prepare_grid(sim, dt);
  const FiberConstraints<Dim> fc(sim.settings(), sim.state(), Real(dt));
  std::vector<int> index;
  const Eigen::SparseMatrix<double> S = fc.schur_matrix(&index);
  ASSERT_GT(S.rows(), 0);
  const SparseGrid<Dim>& grid = sim.grid();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Real> mu(fc.rows(), 0), c0, c1;
  Eigen::VectorXd x(S.rows());
  for (size_t z = 0; z < mu.size(); ++z)
    if (index[z] >= 0) x[index[z]] = mu[z] = Real(u(rng));
  std::vector<Vec<Dim>> w, zero(grid.num_active_nodes(), Vec<Dim>::Zero());
  fc.transpose(mu, &w);
  for (size_t n = 0; n < w.size(); ++n)
    w[n] = grid.mass[n] > 0 ? Vec<Dim>(w[n] / grid.mass[n]) : Vec<Dim>::Zero().eval();
  fc.constraint(zero, &c0);
  fc.constraint(w, &c1);
  // Only the lower triangle is stored.
  for (int j = 0; j < S.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(S, j); it; ++it) EXPECT_GE(it.row(), j);
  const Eigen::VectorXd y = S.selfadjointView<Eigen::Lower>() * x;
  double worst = 0, scale = 0;
  for (size_t z = 0; z < mu.size(); ++z) {
    if (index[z] < 0) continue;
    worst = std::max(worst, std::abs(y[index[z]] - double(c1[z] - c0[z])));
    scale = std::max(scale, std::abs(y[index[z]]));
  }
  EXPECT_LT(worst, 1e-12 * scale);
}

TEST(Inextensibility, SchurMatrixMatchesTheOperator2D) {
  expect_schur_matrix_matches_the_operator<2>();
}
TEST(Inextensibility, SchurMatrixMatchesTheOperator3D) {
  expect_schur_matrix_matches_the_operator<3>();
}

// A 2D bar of length L, fibers along it, its top 4 cells in a sticky box, released from rest
// under gravity for three periods of its first elastic mode.
struct Hanging {
  double elongation = 0;         // time-averaged over the last two periods, (length - L) / L
  double fiber_stretch_max = 0;  // largest |F a0| - 1 over particles and steps
  double tension_error = 0;      // largest |T - rho g h| / (rho g L) at the end (band means)
  long steps = 0;
  InextensibilityStats stats;
  std::vector<Vec<2>> x;  // final positions
};

constexpr double kE = 200, kRho = 1, kL = 0.5, kG = 9.8, kTop = 0.8;

Hanging hanging_bar(bool inextensible, double relaxation = 0,
                    Integrator integrator = Integrator::Explicit, double dt_factor = 1,
                    double dx = 1.0 / 32, double periods = 3,
                    InextensibilityPreconditioner pc = InextensibilityPreconditioner::Cholesky) {
  Scene s = basic_scene(2, dx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::QrAniso, kE, 0.0, kRho, 0);
  s.gravity = Vec3d(0, -kG, 0);
  s.integrator = integrator;
  s.materials[0].inextensibility.enabled = inextensible;
  s.materials[0].inextensibility.relaxation = relaxation;
  s.inextensibility.preconditioner = pc;
  const double grip = kTop - 4 * dx, top = kTop;
  s.boundaries.push_back(sticky_box(2, Vec3d(0, grip, 0), Vec3d(1, 1, 0)));
  Particles<2> p = lattice_block<2>(s, Vec<2>(0.45, Real(grip - kL)), Vec<2>(0.55, Real(top)), 2,
                                    [](const Vec<2>&) { return Vec<2>::Zero().eval(); });
  for (size_t i = 0; i < p.size(); ++i) p.fiber[i] = fiber_frame<2>(Real(1.5707963267948966));
  MpmSim<2> sim(s, std::move(p));
  const double c = std::sqrt(kE / kRho);
  const double dt = dt_factor * 0.4 * dx / c, t_end = periods * 4 * kL / c;
  Hanging h;
  double sum = 0, weight = 0;
  while (sim.time() < t_end) {
    sim.step(dt);
    const Particles<2>& q = sim.particles();
    double low = 1e9;
    for (size_t i = 0; i < q.size(); ++i) {
      low = std::min(low, double(q.x[i][1]));
      h.fiber_stretch_max =
          std::max(h.fiber_stretch_max, double((q.F[i] * q.fiber[i].col(0)).norm()) - 1);
    }
    // The lowest particle sits a quarter cell above the bar's end.
    const double length = grip - (low - 0.25 * dx);
    if (sim.time() > t_end / 3) sum += (length - kL) / kL * dt, weight += dt;
    ++h.steps;
  }
  h.elongation = sum / weight;
  h.stats = sim.inextensibility_stats();
  const Particles<2>& q = sim.particles();
  h.x.assign(q.x.begin(), q.x.end());
  if (inextensible && relaxation == 0) {
    // Mean tension and mean rho g h over bands a tenth of the bar long (a particle's own
    // tension is noisier: multipliers on cells, velocities on nodes).
    // The last two bands, within three cells of the grip, are left out: rows there that the
    // grip holds have no multiplier.
    double t[8] = {}, w[8] = {};
    int n[8] = {};
    for (size_t i = 0; i < q.size(); ++i) {
      const double height = q.x[i][1] - (grip - kL);  // above the free end
      const int b = int(std::floor(height / kL * 10));
      if (b < 0 || b > 7) continue;
      t[b] += q.fiber_tension[i], w[b] += kRho * kG * height, ++n[b];
    }
    for (int b = 0; b < 8; ++b)
      h.tension_error = std::max(h.tension_error, std::abs(t[b] - w[b]) / n[b] / (kRho * kG * kL));
  }
  return h;
}

// The bar does not stretch (an elastic one of the same E stretches by rho g L / 2E on average),
// and its tension is the weight below: T(h) = rho g h.
TEST(Inextensibility, HangingBarDoesNotStretchAndCarriesItsWeight) {
  const Hanging elastic = hanging_bar(false), hard = hanging_bar(true);
  const double expected = kRho * kG * kL / (2 * kE);
  std::printf("hanging bar: elastic elongation %.4f (static %.4f), inextensible %.2e, its "
              "largest fiber stretch %.2e, tension error %.3f; CG %.1f a step, at most %d\n",
              elastic.elongation, expected, hard.elongation, hard.fiber_stretch_max,
              hard.tension_error, double(hard.stats.cg_iterations) / double(hard.steps),
              hard.stats.cg_iterations_max);
  EXPECT_NEAR(elastic.elongation, expected, 0.3 * expected);
  EXPECT_LT(std::abs(hard.elongation), 1e-3);
  EXPECT_LT(hard.fiber_stretch_max, 1e-3);
  EXPECT_LT(hard.tension_error, 0.03);
  EXPECT_EQ(hard.stats.unconverged, 0);
  EXPECT_EQ(hard.stats.solves, hard.steps);
}

// The same under the implicit integrator at ten times the explicit step, and on a finer grid
// for one period.
TEST(Inextensibility, HangingBarHoldsUnderTheImplicitIntegratorAndAtFinerGrids) {
  const Hanging implicit = hanging_bar(true, 0, Integrator::Implicit, 10);
  const Hanging fine = hanging_bar(true, 0, Integrator::Explicit, 1, 1.0 / 64, 1);
  std::printf("implicit at 10x dt: elongation %.2e, stretch %.2e, tension error %.3f, CG %.1f a "
              "step; dx/2: elongation %.2e, stretch %.2e, tension error %.3f, CG %.1f a step\n",
              implicit.elongation, implicit.fiber_stretch_max, implicit.tension_error,
              double(implicit.stats.cg_iterations) / double(implicit.steps), fine.elongation,
              fine.fiber_stretch_max, fine.tension_error,
              double(fine.stats.cg_iterations) / double(fine.steps));
  for (const Hanging* h : {&implicit, &fine}) {
    EXPECT_LT(std::abs(h->elongation), 1e-3);
    EXPECT_LT(h->fiber_stretch_max, 1e-3);
    EXPECT_EQ(h->stats.unconverged, 0);
  }
  EXPECT_LT(fine.tension_error, 0.03);
  // The projection follows Newton's solve, whose elastic forces see the bar stretch within the
  // step: they carry a share of the weight (8 % here), the constraint the rest.
  EXPECT_LT(implicit.tension_error, 0.12);
}

// CG iterations a step as dx halves: the Cholesky preconditioner (an exact factorisation) needs
// one whatever the resolution; Jacobi's count grows with the bar's length in cells.
TEST(Inextensibility, CholeskyPreconditionerKeepsCgIterationsAsTheGridRefines) {
  double mean[2][2];
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) {
      const auto pc = j == 0 ? InextensibilityPreconditioner::Cholesky
                             : InextensibilityPreconditioner::Jacobi;
      const Hanging h = hanging_bar(true, 0, Integrator::Explicit, 1, 1.0 / (16 << k), 0.3, pc);
      mean[k][j] = double(h.stats.cg_iterations) / double(h.stats.solves);
      EXPECT_EQ(h.stats.unconverged, 0);
    }
  std::printf("CG iterations a step at dx = 1/16, 1/32: Cholesky %.1f, %.1f; Jacobi %.1f, %.1f\n",
              mean[0][0], mean[1][0], mean[0][1], mean[1][1]);
  EXPECT_LE(mean[1][0], 2.0);
  EXPECT_GT(mean[1][1] / mean[0][1], 1.5);
  EXPECT_LT(mean[1][0] / mean[0][0], 0.5 * mean[1][1] / mean[0][1]);
}

// The relaxed constraint is a fiber of modulus k in parallel with the material: the bar
// stretches by about rho g L / 2(E + k), less as k grows, towards the hard constraint.
TEST(Inextensibility, RelaxedConstraintTendsToTheHardOneAsItsStiffnessGrows) {
  std::vector<double> e;
  for (const double k : {1.0, 10.0, 100.0}) {
    const Hanging h = hanging_bar(true, k * kE);
    const double expected = kRho * kG * kL / (2 * (kE + k * kE));
    std::printf("relaxation %g E: elongation %.3e, static %.3e\n", k, h.elongation, expected);
    EXPECT_NEAR(h.elongation, expected, 0.2 * expected) << "k = " << k << " E";
    e.push_back(h.elongation);
  }
  EXPECT_GT(e[0], e[1]);
  EXPECT_GT(e[1], e[2]);
}

// Fibers across a cantilever do not lock its bending: its tip drops about as far as without
// the constraint.
TEST(Inextensibility, FibersAcrossABeamDoNotLockItsBending) {
  // fiber_scale: elastic fiber stiffness; spread: each fiber turned by a random angle up to
  // this many degrees (paper Fig. 22's perturbed fibers).
  auto tip_drop = [](bool inextensible, double fiber_scale, double spread) {
    const double dx = 1.0 / 32;
    Scene s = basic_scene(2, dx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::QrAniso, 400, 0.3, 1,
                          fiber_scale);
    s.gravity = Vec3d(0, -9.8, 0);
    s.materials[0].inextensibility.enabled = inextensible;
    s.boundaries.push_back(sticky_box(2, Vec3d(0, 0, 0), Vec3d(0.2, 1, 0)));
    Particles<2> p = lattice_block<2>(s, Vec<2>(0.1, 0.6), Vec<2>(0.7, 0.7), 2,
                                      [](const Vec<2>&) { return Vec<2>::Zero().eval(); });
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> turn(-spread, spread);
    for (size_t i = 0; i < p.size(); ++i)
      p.fiber[i] = fiber_frame<2>(Real((90 + turn(rng)) * 3.14159265358979 / 180));
    const Particles<2> start = p;  // ids in order
    MpmSim<2> sim(s, std::move(p));
    while (sim.time() < 0.25) sim.step(std::min(sim.estimate_dt(), 0.25 - sim.time() + 1e-12));
    const Particles<2>& q = sim.particles();
    const std::vector<uint32_t> row = rows_by_id(q.id);
    double drop = 0;
    for (size_t i = 0; i < start.size(); ++i)
      if (start.x[i][0] > 0.65) drop = std::max(drop, double(start.x[i][1] - q.x[row[i]][1]));
    return drop;
  };
  const double free = tip_drop(false, 0, 0), constrained = tip_drop(true, 0, 0);
  const double perturbed = tip_drop(true, 0, 10);
  std::printf("cantilever tip drop: %.4f without the constraint, %.4f with inextensible fibers "
              "across, %.4f with them perturbed by up to 10 degrees\n",
              free, constrained, perturbed);
  EXPECT_GT(free, 0.02);
  EXPECT_GT(constrained, 0.7 * free);
  EXPECT_GT(perturbed, 0.7 * free);
}

// A bar with fibers along it and a band of broken particles across its middle, pulled apart by
// its ends: the constraint does not hold across the crack, which opens as fast as the ends move
// while the halves keep their length.
TEST(Inextensibility, CrackOpensAcrossInextensibleFibers) {
  const double dx = 1.0 / 32, u = 0.5, t_end = 0.1;
  Scene s = basic_scene(2, dx, Vec3d::Zero(), Vec3d(1, 1, 0), Model::QrAniso, 10, 0.3, 1, 0);
  s.materials[0].inextensibility.enabled = true;
  s.boundaries.push_back(sticky_box(2, Vec3d(0, 0, 0), Vec3d(0.25, 1, 0)));
  s.boundaries.push_back(sticky_box(2, Vec3d(0.75, 0, 0), Vec3d(1, 1, 0), Vec3d(u, 0, 0)));
  Particles<2> p = lattice_block<2>(s, Vec<2>(0.15, 0.45), Vec<2>(0.85, 0.55), 2,
                                    [](const Vec<2>&) { return Vec<2>::Zero().eval(); });
  for (size_t i = 0; i < p.size(); ++i)
    if (std::abs(p.x[i][0] - 0.5) < dx) p.damage[i] = 1;
  const Particles<2> start = p;  // ids in order
  MpmSim<2> sim(s, std::move(p));
  while (sim.time() < t_end - 1e-12) sim.step(std::min(2e-3, t_end - sim.time()));
  const Particles<2>& q = sim.particles();
  const std::vector<uint32_t> row = rows_by_id(q.id);
  double left = 0, right = 0, stretch = 0, mean_stretch[2] = {0, 0};
  int nl = 0, nr = 0, ns[2] = {0, 0};
  for (size_t i = 0; i < start.size(); ++i) {
    if (start.damage[i] > 0) continue;
    const double moved = q.x[row[i]][0] - start.x[i][0];
    if (start.x[i][0] < 0.5) left += moved, ++nl;
    else right += moved, ++nr;
    // The fiber stretch away from the crack's edges (rows reach two cells across them): the
    // constraint holds cell averages, so a particle's own stretch may swing a little.
    if (std::abs(start.x[i][0] - 0.5) > 3 * dx) {
      const double e = double(q.F[row[i]].col(0).norm()) - 1;
      stretch = std::max(stretch, std::abs(e));
      mean_stretch[start.x[i][0] > 0.5] += e, ++ns[start.x[i][0] > 0.5];
    }
  }
  left /= nl, right /= nr;
  for (int h = 0; h < 2; ++h) mean_stretch[h] /= ns[h];
  std::printf("crack: left half moved %.4f, right half %.4f (ends: 0, %.4f), fiber stretch "
              "%.1e and %.1e on average, at most %.1e; CG %ld in %ld solves, at most %d, "
              "residual %.2g\n",
              left, right, u * t_end, mean_stretch[0], mean_stretch[1], stretch,
              sim.inextensibility_stats().cg_iterations, sim.inextensibility_stats().solves,
              sim.inextensibility_stats().cg_iterations_max, sim.inextensibility_stats().residual_max);
  EXPECT_NEAR(left, 0, 0.05 * u * t_end);
  EXPECT_NEAR(right, u * t_end, 0.05 * u * t_end);
  for (int h = 0; h < 2; ++h) EXPECT_LT(std::abs(mean_stretch[h]), 1e-3);
  EXPECT_LT(stretch, 1e-2);
  EXPECT_EQ(sim.inextensibility_stats().unconverged, 0);
}

// Same bits for one and two threads.
TEST(Inextensibility, SameBitsForOneAndTwoThreads) {
  auto run = [](int threads) {
    const ThreadLimit limit(threads);
    return hanging_bar(true, 0, Integrator::Explicit, 1, 1.0 / 32, 0.3).x;
  };
  const std::vector<Vec<2>> a = run(1), b = run(2);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "particle " << i;
}

}  // namespace
}  // namespace tear
