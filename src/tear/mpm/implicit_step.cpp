// The implicit integrator: backward Euler as the minimisation of the incremental potential over
// the grid velocities (mpm/implicit_step.h).
#include "tear/mpm/implicit_step.h"

#include "tear/damage/driving_force.h"
#include "tear/exec/parallel.h"
#include "tear/exec/phase_timer.h"
#include "tear/grid/block_window.h"
#include "tear/mpm/phases.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tear {

template <int Dim>
IncrementalPotential<Dim>::IncrementalPotential(const MpmSettings& settings,
                                                const MpmState<Dim>& state, Real dt)
    : settings_(settings), state_(state), dt_(dt),
      use_multigrid_(settings.implicit_preconditioner == ImplicitPreconditioner::Multigrid ||
                     (settings.implicit_preconditioner == ImplicitPreconditioner::Auto &&
                      state.implicit_multigrid)) {
  const SparseGrid<Dim>& grid = state.grid;
  for (size_t g = 0; g < state.groups.size(); ++g) {
    group_offset_.push_back(refs_.size());
    for (size_t i = 0; i < state.groups[g].size(); ++i) refs_.push_back({uint32_t(g), uint32_t(i)});
  }
  const size_t np = refs_.size();
  nodes_.resize(np);
  grads_.resize(np);
  F_.resize(np);
  degradation_.resize(np);
  parallel_for(np, [&](size_t k) { degradation_[k] = degradation_of(refs_[k]); });
  // Stencils: each home block's window, its nodes' storage indices, the particles' weights.
  const Real inv_d = BSpline1D<kTransferOrder>::kInvD / Real(settings.dx * settings.dx);
  for (size_t g = 0; g < state.groups.size(); ++g) {
    const Particles<Dim>& p = state.groups[g];
    const ParticleBins<Dim>& bins = grid.bins(g);
    parallel_for(bins.home_blocks.size(), [&](size_t b) {
      const auto& h = bins.home_blocks[b];
      const BlockWindow<Dim, kTransferOrder> window(grid, h, p.x, bins.order.data());
      thread_local std::vector<int> storage;
      storage.assign(BlockWindow<Dim, kTransferOrder>::kSize, -1);
      window.for_each_node([&](int wn, int n) { storage[size_t(wn)] = n; });
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t i = bins.order[k];
        const size_t flat = group_offset_[g] + i;
        const Mat<Dim> Ft = p.F[i].transpose();
        int s = 0;
        WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit(
            [&](int wn, Real w, const Vec<Dim>& rel) {
              nodes_[flat][size_t(s)] = storage[size_t(wn)];
              grads_[flat][size_t(s)] = Ft * (w * inv_d * rel);
              ++s;
            });
      }
    });
  }
  // Masses, v*, and the constraints of the walls and colliders at the end of the step.
  const size_t nn = grid.num_active_nodes();
  mass_.assign(nn, 0);
  v_star_.assign(nn * Dim, 0);
  free_.assign(nn, Mat<Dim>::Identity());
  // At the step's start time, as grid_update applied them to v*.
  const NodeContacts<Dim> contacts(grid, settings.walls, settings.colliders, state.time);
  parallel_for(nn, [&](size_t node) {
    mass_[node] = grid.mass[node];
    if (!(mass_[node] > 0)) {
      free_[node].setZero();
      return;
    }
    const Vec<Dim>& v = grid.velocity[node];
    for (int a = 0; a < Dim; ++a) v_star_[node * Dim + a] = v[a];
    free_[node] = free_directions(contacts, int(node), v);
  });
  // The residual's mass floor: a hundredth of the mean node mass.
  size_t massive = 0;
  for (size_t node = 0; node < nn; ++node) massive += mass_[node] > 0;
  const double total =
      deterministic_sum<double>(nn, [&](size_t node) { return double(mass_[node]); });
  residual_mass_ = massive > 0 ? Real(0.01 * total / double(massive)) : Real(0);
}

template <int Dim>
Real IncrementalPotential<Dim>::degradation_of(const ParticleRef& r) const {
  const Particles<Dim>& p = state_.groups[r.group];
  const uint16_t mat = p.material[r.index];
  if (settings_.damage.solver == DamageSolver::None || mat >= settings_.material_damage.size())
    return 1;
  const DamageParams& dp = settings_.material_damage[mat];
  return dp.enabled ? degradation(p.damage[r.index], Real(dp.residual)) : Real(1);
}

template <int Dim>
void IncrementalPotential<Dim>::deformations(const std::vector<Real>& v) {
  parallel_for(refs_.size(), [&](size_t k) {
    const ParticleRef& r = refs_[k];
    Mat<Dim> B = Mat<Dim>::Zero();
    for (int s = 0; s < kStencil; ++s) {
      const Real* vn = &v[size_t(nodes_[k][size_t(s)]) * Dim];
      B += Eigen::Map<const Vec<Dim>>(vn) * grads_[k][size_t(s)].transpose();
    }
    F_[k] = state_.groups[r.group].F[r.index] + dt_ * B;
  });
}

template <int Dim>
template <class Fn>
void IncrementalPotential<Dim>::scatter(Fn&& fn) const {
  // One colour of home blocks at a time: blocks of one colour reach disjoint nodes, so the
  // sums at a node are made in the same order for any thread count.
  scatter_home_blocks(state_, [&](size_t g, const typename SparseGrid<Dim>::HomeBlock& h) {
    const uint32_t* order = state_.grid.bins(g).order.data();
    for (uint32_t k = h.begin; k < h.end; ++k) fn(group_offset_[g] + order[k]);
  });
}

template <int Dim>
double IncrementalPotential<Dim>::energy(const std::vector<Real>& v) {
  deformations(v);
  const double kinetic = deterministic_sum<double>(mass_.size(), [&](size_t node) {
    if (!(mass_[node] > 0)) return 0.0;
    double s = 0;
    for (int a = 0; a < Dim; ++a) {
      const double d = double(v[node * Dim + a]) - double(v_star_[node * Dim + a]);
      s += d * d;
    }
    return 0.5 * double(mass_[node]) * s;
  });
  const double elastic = deterministic_sum<double>(refs_.size(), [&](size_t k) {
    const Particles<Dim>& p = state_.groups[refs_[k].group];
    const size_t i = refs_[k].index;
    const MaterialParams& m = settings_.materials[p.material[i]];
    return double(p.vol0[i]) * double(energy_density<Dim>(m, F_[k], p.fiber_of(i), degradation_[k]));
  });
  return kinetic + elastic;
}

template <int Dim>
void IncrementalPotential<Dim>::gradient(const std::vector<Real>& v, std::vector<Real>& g) {
  deformations(v);
  parallel_for(mass_.size(), [&](size_t node) {
    for (int a = 0; a < Dim; ++a)
      g[node * Dim + a] = mass_[node] * (v[node * Dim + a] - v_star_[node * Dim + a]);
  });
  scatter([&](size_t k) {
    const Particles<Dim>& p = state_.groups[refs_[k].group];
    const size_t i = refs_[k].index;
    const MaterialParams& m = settings_.materials[p.material[i]];
    const Mat<Dim> scaled = (dt_ * p.vol0[i]) * first_piola<Dim>(m, F_[k], p.fiber_of(i), degradation_[k]);
    for (int s = 0; s < kStencil; ++s) {
      Eigen::Map<Vec<Dim>> gn(&g[size_t(nodes_[k][size_t(s)]) * Dim]);
      gn += scaled * grads_[k][size_t(s)];
    }
  });
  project(g);
}

template <int Dim>
void IncrementalPotential<Dim>::project(std::vector<Real>& u) const {
  parallel_for(mass_.size(), [&](size_t node) {
    Eigen::Map<Vec<Dim>> un(&u[node * Dim]);
    un = free_[node] * un;
  });
}

template <int Dim>
double IncrementalPotential<Dim>::residual(const std::vector<Real>& g) const {
  const Real worst = parallel_max<Real>(
      mass_.size(),
      [&](size_t node) {
        if (!(mass_[node] > 0)) return Real(0);
        return Eigen::Map<const Vec<Dim>>(&g[node * Dim]).norm() /
               std::max(mass_[node], residual_mass_);
      },
      Real(0));
  return double(worst) * double(dt_) / settings_.dx;
}

template <int Dim>
void IncrementalPotential<Dim>::prepare_hessian(const std::vector<Real>& v) {
  deformations(v);
  hessian_.resize(refs_.size());
  parallel_for(refs_.size(), [&](size_t k) {
    const Particles<Dim>& p = state_.groups[refs_[k].group];
    const size_t i = refs_[k].index;
    const MaterialParams& m = settings_.materials[p.material[i]];
    hessian_[k] =
        p.vol0[i] * projected_stress_derivative<Dim>(m, F_[k], p.fiber_of(i), degradation_[k]);
  });
  // The Jacobi diagonal: m_i + dt^2 sum_p u^T A_p(a) u for each component a of node i, where
  // u = F^T grad w and A_p(a) the block of the particle's matrix that e_a u^T meets.
  diag_.assign(mass_.size() * Dim, 0);
  const Real dt2 = dt_ * dt_;
  scatter([&](size_t k) {
    const StressDerivative<Dim>& A = hessian_[k];
    for (int s = 0; s < kStencil; ++s) {
      const Vec<Dim>& u = grads_[k][size_t(s)];
      Real* dn = &diag_[size_t(nodes_[k][size_t(s)]) * Dim];
      for (int a = 0; a < Dim; ++a) {
        Real sum = 0;
        for (int c = 0; c < Dim; ++c)
          for (int e = 0; e < Dim; ++e) sum += u[c] * u[e] * A(a + Dim * c, a + Dim * e);
        dn[a] += dt2 * sum;
      }
    }
  });
  parallel_for(mass_.size(), [&](size_t node) {
    for (int a = 0; a < Dim; ++a) diag_[node * Dim + a] += mass_[node];
  });
  // The hierarchy is built at the step's first Newton iteration that uses it and kept for the
  // next three: a preconditioner from a nearby Hessian, at a fraction of the cost (a rebuild
  // each iteration made the stiff cantilever at dt 1e-3 25 % slower for the same CG counts;
  // kept for ever, a 79-iteration solve from a non-convex state took 1.7x the CG iterations).
  if (use_multigrid_) {
    if (!multigrid_ || multigrid_age_ >= 4) build_multigrid();
    ++multigrid_age_;
    ++multigrid_solves_;
  }
}

template <int Dim>
void IncrementalPotential<Dim>::build_multigrid() {
  const std::vector<IVec<Dim>> points = node_coords();
  std::vector<double> free(mass_.size() * Dim * Dim);
  parallel_for(mass_.size(), [&](size_t node) {
    for (int e = 0; e < Dim * Dim; ++e) free[node * Dim * Dim + size_t(e)] = free_[node](e);
  });
  multigrid_ =
      std::make_unique<LatticeMultigrid<Dim>>(points, Dim, 2, assemble_hessian(points), free);
  multigrid_age_ = 0;
}

template <int Dim>
void IncrementalPotential<Dim>::strengthen_preconditioner() {
  use_multigrid_ = true;
  build_multigrid();
  ++multigrid_age_;
  ++multigrid_solves_;
}

template <int Dim>
std::vector<IVec<Dim>> IncrementalPotential<Dim>::node_coords() const {
  std::vector<IVec<Dim>> coord(mass_.size());
  parallel_for(coord.size(), [&](size_t node) { coord[node] = state_.grid.node_coord(int(node)); });
  return coord;
}

template <int Dim>
Eigen::SparseMatrix<double, Eigen::RowMajor> IncrementalPotential<Dim>::hessian_matrix() const {
  return assemble_hessian(node_coords());
}

template <int Dim>
Eigen::SparseMatrix<double, Eigen::RowMajor> IncrementalPotential<Dim>::assemble_hessian(
    const std::vector<IVec<Dim>>& coord) const {
  // Blocks between a node and the nodes within two cells of it (5 per axis), accumulated over
  // the particles, one colour of home blocks at a time (deterministic like scatter).
  constexpr int kReach = Dim == 2 ? 25 : 125;
  constexpr int kBlock = Dim * Dim;
  const size_t nn = mass_.size();
  std::vector<double> blocks(nn * kReach * kBlock, 0.0);
  std::vector<int> neighbour(nn * kReach, -1);
  const double dt2 = double(dt_) * double(dt_);
  scatter([&](size_t k) {
    const StressDerivative<Dim>& A = hessian_[k];
    const auto& nodes = nodes_[k];
    const auto& u = grads_[k];
    for (int s = 0; s < kStencil; ++s) {
      // M(a, j) = sum_c u_s[c] A(a + Dim c, j): the force on s's component a per unit dF_j.
      Eigen::Matrix<double, Dim, Dim * Dim> M = Eigen::Matrix<double, Dim, Dim * Dim>::Zero();
      for (int a = 0; a < Dim; ++a)
        for (int c = 0; c < Dim; ++c)
          M.row(a) += double(u[size_t(s)][c]) * A.row(a + Dim * c).template cast<double>();
      const int ns = nodes[size_t(s)];
      for (int t = 0; t < kStencil; ++t) {
        const int nt = nodes[size_t(t)];
        int slot = 0;
        for (int d = Dim - 1; d >= 0; --d) slot = slot * 5 + (coord[size_t(nt)][d] - coord[size_t(ns)][d] + 2);
        neighbour[size_t(ns) * kReach + size_t(slot)] = nt;
        double* blk = &blocks[(size_t(ns) * kReach + size_t(slot)) * kBlock];
        for (int b = 0; b < Dim; ++b)
          for (int e = 0; e < Dim; ++e) {
            const double ue = dt2 * double(u[size_t(t)][e]);
            for (int a = 0; a < Dim; ++a) blk[a + Dim * b] += M(a, b + Dim * e) * ue;
          }
      }
    }
  });
  // Rows: node by node, its neighbours in storage order; P (M + dt^2 K) P on the free
  // directions, the identity on the others (P = free_).
  constexpr int kCentre = Dim == 2 ? 12 : 62;
  std::vector<int> count(nn + 1, 0);
  parallel_for(nn, [&](size_t node) {
    int c = 0;
    for (int slot = 0; slot < kReach; ++slot)
      if (neighbour[node * kReach + size_t(slot)] >= 0 || slot == kCentre) ++c;
    count[node + 1] = c * Dim;
  });
  for (size_t node = 0; node < nn; ++node) count[node + 1] += count[node];
  Eigen::SparseMatrix<double, Eigen::RowMajor> H(Eigen::Index(nn * Dim), Eigen::Index(nn * Dim));
  H.resizeNonZeros(Eigen::Index(count[nn]) * Dim);
  int* outer = H.outerIndexPtr();
  int* inner = H.innerIndexPtr();
  double* value = H.valuePtr();
  for (size_t node = 0; node < nn; ++node)
    for (int a = 0; a < Dim; ++a) outer[node * Dim + size_t(a)] = Dim * count[node] + a * (count[node + 1] - count[node]);
  outer[nn * Dim] = Dim * count[nn];
  parallel_for(nn, [&](size_t node) {
    std::array<std::pair<int, int>, kReach> list;  // (neighbour, slot)
    int n = 0;
    for (int slot = 0; slot < kReach; ++slot) {
      const int j = slot == kCentre ? int(node) : neighbour[node * kReach + size_t(slot)];
      if (j >= 0) list[size_t(n++)] = {j, slot};
    }
    std::sort(list.begin(), list.begin() + n);
    const Mat<Dim>& Pi = free_[node];
    for (int a = 0; a < Dim; ++a) {
      int pos = outer[node * Dim + size_t(a)];
      for (int q = 0; q < n; ++q) {
        const auto [j, slot] = list[size_t(q)];
        const Eigen::Map<const Eigen::Matrix<double, Dim, Dim>> K(
            &blocks[(node * kReach + size_t(slot)) * kBlock]);
        Eigen::Matrix<double, Dim, Dim> blk =
            Pi.template cast<double>() * K * free_[size_t(j)].template cast<double>();
        if (j == int(node)) {
          const Eigen::Matrix<double, Dim, Dim> I = Eigen::Matrix<double, Dim, Dim>::Identity();
          blk += double(mass_[node]) * Pi.template cast<double>() + (I - Pi.template cast<double>());
        }
        for (int b = 0; b < Dim; ++b) {
          inner[pos] = j * Dim + b;
          value[pos] = blk(a, b);
          ++pos;
        }
      }
    }
  });
  return H;
}

template <int Dim>
void IncrementalPotential<Dim>::apply_hessian(const std::vector<Real>& d,
                                              std::vector<Real>& y) const {
  std::vector<Real>& dp = scratch_;
  dp = d;
  project(dp);
  parallel_for(mass_.size(), [&](size_t node) {
    for (int a = 0; a < Dim; ++a) y[node * Dim + a] = mass_[node] * dp[node * Dim + a];
  });
  scatter([&](size_t k) {
    Mat<Dim> B = Mat<Dim>::Zero();
    for (int s = 0; s < kStencil; ++s)
      B += Eigen::Map<const Vec<Dim>>(&dp[size_t(nodes_[k][size_t(s)]) * Dim]) *
           grads_[k][size_t(s)].transpose();
    const Vec<Dim * Dim> dP = hessian_[k] * (dt_ * B).reshaped();
    const Mat<Dim> dPm = Eigen::Map<const Mat<Dim>>(dP.data()) * dt_;
    for (int s = 0; s < kStencil; ++s) {
      Eigen::Map<Vec<Dim>> yn(&y[size_t(nodes_[k][size_t(s)]) * Dim]);
      yn += dPm * grads_[k][size_t(s)];
    }
  });
  project(y);
}

template <int Dim>
void IncrementalPotential<Dim>::precondition(const std::vector<Real>& r,
                                             std::vector<Real>& z) const {
  if (multigrid_) {
    mg_r_.resize(Eigen::Index(r.size()));
    for (size_t i = 0; i < r.size(); ++i) mg_r_[Eigen::Index(i)] = double(r[i]);
    multigrid_->apply(mg_r_, mg_z_);
    for (size_t i = 0; i < z.size(); ++i) z[i] = active(i) ? Real(mg_z_[Eigen::Index(i)]) : Real(0);
    return;
  }
  parallel_for(mass_.size(), [&](size_t node) {
    Vec<Dim> zn;
    for (int a = 0; a < Dim; ++a) {
      const Real dd = diag_[node * Dim + a];
      zn[a] = dd > 0 ? r[node * Dim + a] / dd : Real(0);
    }
    Eigen::Map<Vec<Dim>> zm(&z[node * Dim]);
    zm = free_[node] * zn;
  });
}

template <int Dim>
double implicit_step(const MpmSettings& settings, MpmState<Dim>* state, double dt,
                     StepRecord* record, Domain& domain) {
  if (settings.damage.split_fields)
    throw std::invalid_argument("the implicit integrator does not support crack fields");
  PhaseTimes& t = record->times;
  return integrate_step(settings, state, dt, record, domain, [&](double h) {
    {
      PhaseTimer timer(&t.p2g);
      p2g(settings, state, Real(0));  // mass and momentum; the stress enters the solve
    }
    PhaseTimer timer(&t.grid);
    grid_update(settings, state, Real(h));  // v*: gravity, walls and colliders
    IncrementalPotential<Dim> potential(settings, *state, Real(h));
    std::vector<Real> v = potential.initial();
    const NewtonResult r = newton_minimize(potential, &v, settings.newton);
    SparseGrid<Dim>& grid = state->grid;
    parallel_for(grid.num_active_nodes(), [&](size_t node) {
      if (grid.mass[node] > 0) grid.velocity[node] = Eigen::Map<const Vec<Dim>>(&v[node * Dim]);
    });
    apply_colliders<Dim>(grid, settings.walls, settings.colliders, state->time);
    ImplicitSolveStats& s = record->implicit;
    ++s.solves;
    s.newton_iterations += r.iterations;
    s.newton_iterations_max = std::max(s.newton_iterations_max, r.iterations);
    s.cg_iterations += r.cg_iterations;
    s.residual_max = std::max(s.residual_max, r.residual);
    if (!r.converged) ++s.unconverged;
    s.multigrid_solves += potential.multigrid_solves();
    if (potential.multigrid_solves() > 0) state->implicit_multigrid = true;
  });
}

template class IncrementalPotential<2>;
template class IncrementalPotential<3>;
template double implicit_step<2>(const MpmSettings&, MpmState<2>*, double, StepRecord*, Domain&);
template double implicit_step<3>(const MpmSettings&, MpmState<3>*, double, StepRecord*, Domain&);

}  // namespace tear
