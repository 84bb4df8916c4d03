// Directional inextensibility: the fiber constraints of a step and the velocity projection
// (mpm/inextensibility.h).
#include "tear/mpm/inextensibility.h"

#include "tear/exec/parallel.h"
#include "tear/grid/collider.h"
#include "tear/kernels/bspline.h"
#include "tear/mpm/phases.h"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tear {

bool has_inextensibility(const MpmSettings& settings) {
  for (const InextensibleParams& m : settings.material_inextensibility)
    if (m.enabled) return true;
  return false;
}

namespace {

// A particle's two stencils: the quadratic one over nodes (base .. base + 2 per axis) and the
// linear one over cell centres (cells base .. base + 1, a cell named by its lower corner node).
// Both start at floor(x / dx - 1/2).
template <int Dim>
struct FiberStencil {
  IVec<Dim> base;
  Real w[Dim][3], rel[Dim][3], gamma[Dim][2];

  FiberStencil(const SparseGrid<Dim>& grid, const Vec<Dim>& x) {
    const Real inv_dx = Real(1 / grid.dx());
    for (int d = 0; d < Dim; ++d) {
      const Real xg = (x[d] - grid.origin()[d]) * inv_dx;
      const BSpline1D<2> s(xg);
      base[d] = s.base;
      for (int k = 0; k < 3; ++k) {
        w[d][k] = s.w[k];
        rel[d][k] = (Real(s.base + k) - xg) * Real(grid.dx());
      }
      const Real f = xg - Real(0.5) - Real(s.base);  // in [0, 1)
      gamma[d][0] = 1 - f, gamma[d][1] = f;
    }
  }
};

// A particle's part in the constraints: its weight W = (1 - d) J V0 (0: none), world fiber,
// target stretch rate and relaxation stiffness.
template <int Dim>
struct FiberPart {
  Real weight = 0, rate = 0, stiffness = 0;
  Vec<Dim> a = Vec<Dim>::Zero();

  FiberPart(const MpmSettings& settings, const Particles<Dim>& p, size_t i, Real dt) {
    const uint16_t mat = p.material[i];
    if (mat >= settings.material_inextensibility.size()) return;
    const InextensibleParams& ip = settings.material_inextensibility[mat];
    const Real d = p.damage[i];
    if (!ip.enabled || !(d < Real(0.5))) return;
    const Real J = p.F[i].determinant();
    const Vec<Dim> fa = p.F[i] * p.fiber_of(i).col(0);
    const Real s = fa.norm();
    if (!(J > 0) || !(s > Real(1e-6))) return;
    weight = (1 - d) * J * p.vol0[i];
    a = fa / s;
    stiffness = Real(ip.relaxation);
    // Relaxed: the fiber's stretch counts (an elastic fiber); hard: its rate only (see the
    // header).
    if (stiffness > 0) rate = (1 / (s * s) - 1) / (2 * dt);
  }
};

// Calls fn(offset) for every offset in {0 .. n - 1}^Dim, x fastest.
template <int Dim, class Fn>
void for_each_offset(int n, Fn&& fn) {
  IVec<Dim> o = IVec<Dim>::Zero();
  while (true) {
    fn(o);
    int d = 0;
    while (d < Dim && ++o[d] == n) o[d++] = 0;
    if (d == Dim) return;
  }
}

template <int Dim>
int slot_index(const IVec<Dim>& o) {  // o in {0 .. 3}^Dim
  int s = 0;
  for (int d = Dim - 1; d >= 0; --d) s = s * 4 + o[d];
  return s;
}

}  // namespace

template <int Dim>
FiberConstraints<Dim>::FiberConstraints(const MpmSettings& settings, const MpmState<Dim>& state,
                                        Real dt)
    : settings_(settings), grid_(state.grid), dt_(dt) {
  const SparseGrid<Dim>& grid = state.grid;
  if (grid.split()) throw std::invalid_argument("inextensibility does not support crack fields");
  const size_t nn = grid.num_active_nodes();
  const Real inv_d = BSpline1D<2>::kInvD / Real(grid.dx() * grid.dx());

  // Calls fn(part, stencil) for every particle taking part, home block by home block, one
  // colour at a time (grid/sparse_grid.h): the cells of blocks of a colour are disjoint.
  auto scatter = [&](auto&& fn) {
    scatter_home_blocks(state, [&](size_t g, const typename SparseGrid<Dim>::HomeBlock& h) {
      const Particles<Dim>& p = state.groups[g];
      const uint32_t* order = grid.bins(g).order.data();
      for (uint32_t k = h.begin; k < h.end; ++k) {
        const uint32_t i = order[k];
        const FiberPart<Dim> pt(settings, p, i, dt);
        if (pt.weight > 0) fn(pt, FiberStencil<Dim>(grid, p.x[i]));
      }
    });
  };

  // The rows: cells that a taking part particle's linear stencil reaches, in storage order.
  std::vector<int>& row_of = row_of_;
  row_of.assign(nn, -1);
  scatter([&](const FiberPart<Dim>&, const FiberStencil<Dim>& st) {
    for_each_offset<Dim>(2, [&](const IVec<Dim>& c) { row_of[size_t(grid.node_index(st.base + c))] = 0; });
  });
  std::vector<int>& cell_node = cell_node_;
  cell_node.clear();
  for (size_t n = 0; n < nn; ++n)
    if (row_of[n] == 0) {
      row_of[n] = int(cell_node.size());
      cell_node.push_back(int(n));
    }
  const size_t rows = cell_node.size();
  node_.resize(rows);
  coef_.assign(rows, {});
  for (auto& r : coef_) r.fill(Vec<Dim>::Zero());
  volume_.assign(rows, 0);
  target_.assign(rows, 0);
  compliance_.assign(rows, 0);
  colours_.assign(size_t(1) << (2 * Dim), {});
  for (size_t z = 0; z < rows; ++z) {
    const IVec<Dim> c = grid.node_coord(cell_node[z]);
    for_each_offset<Dim>(4, [&](const IVec<Dim>& o) {
      node_[z][size_t(slot_index<Dim>(o))] = grid.node_index(c + o - IVec<Dim>::Ones());
    });
    // Rows whose cells agree mod 4 on every axis reach disjoint nodes.
    colours_[size_t(slot_index<Dim>(IVec<Dim>(c.unaryExpr([](int v) { return v & 3; }))))]
        .push_back(uint32_t(z));
  }

  // B's entries, the rows' volumes, target rates and compliances.
  const Real inv_dt2 = 1 / (dt * dt);
  scatter([&](const FiberPart<Dim>& pt, const FiberStencil<Dim>& st) {
    for_each_offset<Dim>(2, [&](const IVec<Dim>& c) {
      Real gamma = pt.weight;
      for (int d = 0; d < Dim; ++d) gamma *= st.gamma[d][c[d]];
      const size_t z = size_t(row_of[size_t(grid.node_index(st.base + c))]);
      volume_[z] += gamma;
      target_[z] += gamma * pt.rate;
      if (pt.stiffness > 0) compliance_[z] += gamma * inv_dt2 / pt.stiffness;
      for_each_offset<Dim>(3, [&](const IVec<Dim>& k) {
        Real wk = inv_d;
        Vec<Dim> rel;
        for (int d = 0; d < Dim; ++d) wk *= st.w[d][k[d]], rel[d] = st.rel[d][k[d]];
        const int slot = slot_index<Dim>(IVec<Dim>(k - c + IVec<Dim>::Ones()));
        coef_[z][size_t(slot)] += (gamma * wk * pt.a.dot(rel)) * pt.a;
      });
    });
  });

  // m^-1 P at the nodes the rows reach (zero elsewhere), and the diagonal of
  // B m^-1 P B^T + K.
  std::vector<char> reached(nn, 0);
  for (size_t z = 0; z < rows; ++z)
    for (int n : node_[z])
      if (n >= 0) reached[size_t(n)] = 1;
  const NodeContacts<Dim> contacts(grid, settings.walls, settings.colliders, state.time);
  mobility_.assign(nn, Mat<Dim>::Zero());
  parallel_for(nn, [&](size_t n) {
    const Real m = grid.mass[n];
    if (reached[n] && m > 0)
      mobility_[n] = free_directions(contacts, int(n), grid.velocity[n]) / m;
  });
  diag_.assign(rows, 0);
  const Real min_volume = Real(0.1 * std::pow(grid.dx(), Dim));
  parallel_for(rows, [&](size_t z) {
    if (volume_[z] < min_volume) return;  // the material barely reaches the cell: no row
    Real s = 0, unheld = 0;
    for (int k = 0; k < kSlots; ++k) {
      const int n = node_[z][size_t(k)];
      if (n < 0 || !(grid.mass[size_t(n)] > 0)) continue;
      const Vec<Dim>& b = coef_[z][size_t(k)];
      s += b.dot(mobility_[size_t(n)] * b);
      unheld += b.squaredNorm() / grid.mass[size_t(n)];
    }
    // Rows that walls and colliders hold for the most part: their multipliers barely move a
    // node, and CG would push them to huge values that do nothing but slow it down.
    if (s < Real(0.25) * unheld) return;
    diag_[z] = s + compliance_[z];
  });
}

template <int Dim>
void FiberConstraints<Dim>::constraint(const std::vector<Vec<Dim>>& v, std::vector<Real>* c) const {
  c->resize(rows());
  parallel_for(rows(), [&](size_t z) {
    Real s = 0;
    for (int k = 0; k < kSlots; ++k) {
      const int n = node_[z][size_t(k)];
      if (n >= 0) s += coef_[z][size_t(k)].dot(v[size_t(n)]);
    }
    (*c)[z] = s - target_[z];
  });
}

template <int Dim>
void FiberConstraints<Dim>::transpose(const std::vector<Real>& mu, std::vector<Vec<Dim>>* u) const {
  u->assign(grid_.num_active_nodes(), Vec<Dim>::Zero());
  for (const std::vector<uint32_t>& colour : colours_)
    parallel_for(colour.size(), [&](size_t j) {
      const size_t z = colour[j];
      for (int k = 0; k < kSlots; ++k) {
        const int n = node_[z][size_t(k)];
        if (n >= 0) (*u)[size_t(n)] += mu[z] * coef_[z][size_t(k)];
      }
    });
}

template <int Dim>
double FiberConstraints<Dim>::strain_error(const std::vector<Vec<Dim>>& v) const {
  std::vector<Real> c;
  constraint(v, &c);
  return parallel_max<double>(
      rows(),
      [&](size_t z) { return diag_[z] > 0 ? std::abs(double(c[z])) / double(volume_[z]) : 0.0; },
      0.0) *
         double(dt_);
}

template <int Dim>
Eigen::SparseMatrix<double> FiberConstraints<Dim>::schur_matrix(std::vector<int>* index) const {
  // The active rows, numbered in row order.
  const size_t rows = this->rows();
  index->assign(rows, -1);
  int n_active = 0;
  for (size_t z = 0; z < rows; ++z)
    if (diag_[z] > 0) (*index)[z] = n_active++;
  // Each active row's entries: rows whose cells are within 3 of its cell on every axis share
  // nodes with it. S is symmetric: only its lower triangle is built (what the factorisation
  // reads), row by row (columns sorted), then taken as a column-major matrix.
  constexpr int kReach = 7, kNear = Dim == 2 ? 49 : 343;
  std::vector<std::vector<std::pair<int, double>>> entries(static_cast<size_t>(n_active));
  parallel_for(rows, [&](size_t z) {
    const int iz = (*index)[z];
    if (iz < 0) return;
    const IVec<Dim> cz = grid_.node_coord(cell_node_[z]);
    std::array<int, kNear> near, near_row;  // active index and row at each offset, or -1
    std::array<double, kNear> sum;
    for_each_offset<Dim>(kReach, [&](const IVec<Dim>& o) {
      int k = 0;
      for (int d = Dim - 1; d >= 0; --d) k = k * kReach + o[d];
      const int n = grid_.node_index(cz + o - IVec<Dim>::Constant(3));
      const int y = n < 0 ? -1 : row_of_[size_t(n)];
      near[size_t(k)] = y < 0 ? -1 : (*index)[size_t(y)];
      near_row[size_t(k)] = y;
      sum[size_t(k)] = 0;
    });
    // Slot a of row z is node cz - 1 + a; it is slot b of the row at cell cz + a - b.
    for_each_offset<Dim>(4, [&](const IVec<Dim>& a) {
      const int n = node_[z][size_t(slot_index<Dim>(a))];
      if (n < 0) return;
      const Vec<Dim> w = mobility_[size_t(n)] * coef_[z][size_t(slot_index<Dim>(a))];
      if (w.isZero()) return;
      for_each_offset<Dim>(4, [&](const IVec<Dim>& b) {
        int k = 0;
        for (int d = Dim - 1; d >= 0; --d) k = k * kReach + (a[d] - b[d] + 3);
        if (near[size_t(k)] < iz) return;  // none there, or above the diagonal
        const size_t zy = size_t(near_row[size_t(k)]);
        sum[size_t(k)] += double(coef_[zy][size_t(slot_index<Dim>(b))].dot(w));
      });
    });
    std::vector<std::pair<int, double>>& e = entries[size_t(iz)];
    for (int k = 0; k < kNear; ++k)
      if (near[size_t(k)] >= iz && (sum[size_t(k)] != 0 || near[size_t(k)] == iz))
        e.emplace_back(near[size_t(k)], sum[size_t(k)] + (near[size_t(k)] == iz ? compliance_[z] : 0));
    std::sort(e.begin(), e.end());
  });
  Eigen::SparseMatrix<double> S(n_active, n_active);
  std::vector<int> counts(static_cast<size_t>(n_active));
  for (int i = 0; i < n_active; ++i) counts[size_t(i)] = int(entries[size_t(i)].size());
  S.reserve(counts);
  for (int i = 0; i < n_active; ++i)
    for (const auto& [j, v] : entries[size_t(i)]) S.insert(j, i) = v;
  S.makeCompressed();
  return S;
}

template <int Dim>
PcgResult FiberConstraints<Dim>::project(std::vector<Vec<Dim>>* v,
                                         const InextensibilitySettings& solve,
                                         std::vector<Real>* mu_out) const {
  const auto active = [&](size_t z) { return diag_[z] > 0; };
  std::vector<Real> rhs;
  constraint(*v, &rhs);
  for (size_t z = 0; z < rows(); ++z)
    if (!active(z)) rhs[z] = 0;  // rows no velocity can change (every node held)
  std::vector<Vec<Dim>> u;
  const auto apply = [&](const std::vector<Real>& mu, std::vector<Real>& y) {
    transpose(mu, &u);
    parallel_for(u.size(), [&](size_t n) { u[n] = mobility_[n] * u[n]; });
    parallel_for(rows(), [&](size_t z) {
      if (!active(z)) {
        y[z] = 0;
        return;
      }
      Real s = compliance_[z] * mu[z];
      for (int k = 0; k < kSlots; ++k) {
        const int n = node_[z][size_t(k)];
        if (n >= 0) s += coef_[z][size_t(k)].dot(u[size_t(n)]);
      }
      y[z] = s;
    });
  };
  std::vector<Real> local;
  std::vector<Real>& mu = mu_out ? *mu_out : local;
  mu.assign(rows(), 0);
  PcgResult res;
  const auto jacobi = [&](const std::vector<Real>& r, std::vector<Real>& z) {
    parallel_for(r.size(), [&](size_t i) { z[i] = active(i) ? r[i] / diag_[i] : Real(0); });
  };
  bool factored = false;
  if (solve.preconditioner == InextensibilityPreconditioner::Cholesky) {
    // The Schur complement, factored: CG converges in one or two iterations. Rows that are
    // nearly dependent (S is only semi-definite) get a relative shift of 1e-10 on the
    // diagonal, which CG's iterations then correct; should the factorisation still fail, the
    // step falls back to Jacobi.
    std::vector<int> index;
    Eigen::SparseMatrix<double> S = schur_matrix(&index);
    for (int i = 0; i < S.rows(); ++i) S.coeffRef(i, i) *= 1 + 1e-10;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt(S);
    factored = ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0).all();
    if (factored) {
      Eigen::VectorXd r_active(S.rows()), z_active;
      const auto cholesky = [&](const std::vector<Real>& r, std::vector<Real>& z) {
        for (size_t i = 0; i < r.size(); ++i)
          if (index[i] >= 0) r_active[index[i]] = double(r[i]);
        z_active = ldlt.solve(r_active);
        for (size_t i = 0; i < r.size(); ++i)
          z[i] = index[i] >= 0 ? Real(z_active[index[i]]) : Real(0);
      };
      res = pcg_solve(apply, cholesky, active, rhs, solve.tolerance, solve.max_iterations, &mu);
    }
  }
  if (!factored) {
    res = pcg_solve(apply, jacobi, active, rhs, solve.tolerance, solve.max_iterations, &mu);
  }
  transpose(mu, &u);
  parallel_for(u.size(), [&](size_t n) { (*v)[n] -= mobility_[n] * u[n]; });
  return res;
}

template <int Dim>
void FiberConstraints<Dim>::store_tensions(const std::vector<Real>& mu,
                                           Particles<Dim>* p) const {
  if (!p->enabled("fiber_tension")) return;
  parallel_for(p->size(), [&](size_t i) {
    Real t = 0;
    if (FiberPart<Dim>(settings_, *p, i, dt_).weight > 0) {
      const FiberStencil<Dim> st(grid_, p->x[i]);
      for_each_offset<Dim>(2, [&](const IVec<Dim>& c) {
        Real gamma = 1;
        for (int d = 0; d < Dim; ++d) gamma *= st.gamma[d][c[d]];
        const int z = row_of_[size_t(grid_.node_index(st.base + c))];
        if (z >= 0 && diag_[size_t(z)] > 0) t += gamma * mu[size_t(z)];
      });
    }
    p->fiber_tension[i] = t / dt_;
  });
}

template <int Dim>
void enforce_inextensibility(const MpmSettings& settings, MpmState<Dim>* state, Real dt,
                             InextensibilityStats* stats) {
  if (!has_inextensibility(settings)) return;
  const FiberConstraints<Dim> constraints(settings, *state, dt);
  if (constraints.rows() == 0) return;
  std::vector<Real> mu;
  const PcgResult r = constraints.project(&state->grid.velocity, settings.inextensibility, &mu);
  for (Particles<Dim>& p : state->groups) constraints.store_tensions(mu, &p);
  ++stats->solves;
  stats->cg_iterations += r.iterations;
  stats->cg_iterations_max = std::max(stats->cg_iterations_max, r.iterations);
  stats->residual_max = std::max(stats->residual_max, r.residual);
  if (!r.converged) ++stats->unconverged;
}

template class FiberConstraints<2>;
template class FiberConstraints<3>;
template void enforce_inextensibility<2>(const MpmSettings&, MpmState<2>*, Real,
                                         InextensibilityStats*);
template void enforce_inextensibility<3>(const MpmSettings&, MpmState<3>*, Real,
                                         InextensibilityStats*);

}  // namespace tear
