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
#include <limits>
#include <stdexcept>

namespace tear {

namespace {

// An element's tangent coefficients at its corner c: the tangent columns of F change by
// sum_c u_c t_c^T for corner displacements u_c (t_c = row c - 1 of D^-1's tangent block for
// c >= 1, corner 0 minus their sum; normal entries zero).
template <int Dim>
Vec<Dim> tangent_coefficients(const Mat<Dim>& rest_inverse, int gamma, int c) {
  Vec<Dim> t = Vec<Dim>::Zero();
  if (c > 0) {
    for (int j = 0; j < gamma; ++j) t[j] = rest_inverse(c - 1, j);
    return t;
  }
  for (int b = 0; b < gamma; ++b)
    for (int j = 0; j < gamma; ++j) t[j] -= rest_inverse(b, j);
  return t;
}

// F's normal columns, the tangent ones zero.
template <int Dim>
Mat<Dim> normal_columns(const Mat<Dim>& F, int gamma) {
  Mat<Dim> N = F;
  for (int j = 0; j < gamma; ++j) N.col(j).setZero();
  return N;
}

}  // namespace

template <int Dim>
IncrementalPotential<Dim>::IncrementalPotential(const MpmSettings& settings,
                                                const MpmState<Dim>& state, Real dt)
    : settings_(settings), state_(state), dt_(dt),
      use_multigrid_(settings.implicit_preconditioner == ImplicitPreconditioner::Multigrid ||
                     (settings.implicit_preconditioner == ImplicitPreconditioner::Auto &&
                      state.implicit_multigrid)) {
  codim_ = state.has_codim();
  const SparseGrid<Dim>& grid = state.grid;
  codim_begin_ = std::numeric_limits<size_t>::max();
  for (size_t g = 0; g < state.groups.size(); ++g) {
    group_offset_.push_back(refs_.size());
    const GroupKind kind = state.groups[g].kind;
    if (kind != GroupKind::Volumetric) codim_begin_ = std::min(codim_begin_, refs_.size());
    for (size_t i = 0; i < state.groups[g].size(); ++i) {
      if (element_dimension(kind) > 0) elements_.push_back(refs_.size());
      refs_.push_back({uint32_t(g), uint32_t(i)});
    }
  }
  const size_t np = refs_.size();
  if (codim_) {
    use_multigrid_ = false;  // see can_strengthen_preconditioner
    const size_t nc = np - codim_begin_;
    weights_.resize(nc);
    vertex_u_.resize(nc);
    vertex_f_.resize(nc);
    vertex_G_.resize(nc);
    vertex_S_.resize(nc);
    element_load_.resize(nc);
    element_normal_load_.resize(nc);
    vertex_x_.resize(nc);
    hinge_hessian_.resize(state.groups.size());
  } else {
    codim_begin_ = np;
  }
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
        // A mesh vertex's F is not a deformation (the identity): its plain weight gradients.
        const bool vertex = p.kind == GroupKind::MeshVertices;
        const Mat<Dim> Ft = vertex ? Mat<Dim>::Identity() : Mat<Dim>(p.F[i].transpose());
        int s = 0;
        WindowStencil<Dim, kTransferOrder>(window, p.x[i]).visit(
            [&](int wn, Real w, const Vec<Dim>& rel) {
              nodes_[flat][size_t(s)] = storage[size_t(wn)];
              grads_[flat][size_t(s)] = Ft * (w * inv_d * rel);
              if (vertex) weights_[flat - codim_begin_][size_t(s)] = w;
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
void IncrementalPotential<Dim>::gather_vertices(const std::vector<Real>& u) const {
  parallel_for(refs_.size() - codim_begin_, [&](size_t c) {
    const size_t k = codim_begin_ + c;
    if (!is_kind(k, GroupKind::MeshVertices)) return;
    Vec<Dim> value = Vec<Dim>::Zero();
    Mat<Dim> gradient = Mat<Dim>::Zero();
    for (int s = 0; s < kStencil; ++s) {
      const Eigen::Map<const Vec<Dim>> un(&u[size_t(nodes_[k][size_t(s)]) * Dim]);
      value += weights_[c][size_t(s)] * un;
      gradient += un * grads_[k][size_t(s)].transpose();
    }
    vertex_u_[c] = value;
    vertex_G_[c] = gradient;
  });
}

template <int Dim>
void IncrementalPotential<Dim>::load_hinges(bool hessian) const {
  for (size_t g = 0; g < state_.groups.size(); ++g) {
    const Particles<Dim>& el = state_.groups[g];
    if (element_dimension(el.kind) == 0 || el.hinges.size() == 0) continue;
    const auto& H = el.hinges;
    const size_t first = group_offset_[size_t(el.vertex_group)] - codim_begin_;
    const bool curve = element_dimension(el.kind) == 1;
    hinge_load_.resize(H.corner.size());
    parallel_for(H.size(), [&](size_t h) {
      Vec<Dim>* out = &hinge_load_[H.begin[h]];
      if (!hessian) return hinge_gradient(el, h, &vertex_x_[first], out);
      hinge_hessian_product(el, h, curve ? &hinge_hessian_[g][h] : nullptr, &vertex_u_[first], out);
      for (uint32_t c = 0; c < H.corners(h); ++c) out[c] *= dt_;
    });
    const size_t nv = state_.groups[size_t(el.vertex_group)].size();
    parallel_for(nv, [&](size_t v) {
      Vec<Dim> f = Vec<Dim>::Zero();
      for (uint32_t q = H.vertex_begin[v]; q < H.vertex_begin[v + 1]; ++q) f += hinge_load_[H.incident[q]];
      vertex_f_[first + v] += f;
    });
  }
}

template <int Dim>
Mat<Dim> IncrementalPotential<Dim>::element_rate(size_t k) const {
  const Particles<Dim>& el = state_.groups[refs_[k].group];
  const size_t i = refs_[k].index;
  const int gamma = element_dimension(el.kind);
  const size_t first = group_offset_[size_t(el.vertex_group)] - codim_begin_;
  Mat<Dim> rate = Mat<Dim>::Zero(), G = Mat<Dim>::Zero();
  for (int c = 0; c <= gamma; ++c) {
    const size_t vc = first + el.element_vertices[i][size_t(c)];
    rate += vertex_u_[vc] * tangent_coefficients<Dim>(el.rest_inverse[i], gamma, c).transpose();
    G += vertex_G_[vc];
  }
  return rate + (G / Real(gamma + 1)) * normal_columns<Dim>(el.F[i], gamma);
}

template <int Dim>
void IncrementalPotential<Dim>::load_vertices() const {
  for (const Particles<Dim>& el : state_.groups) {
    const int gamma = element_dimension(el.kind);
    if (gamma == 0) continue;
    const size_t vg = size_t(el.vertex_group);
    const Particles<Dim>& vx = state_.groups[vg];
    const size_t corners = size_t(gamma + 1);
    if (vx.incident_begin.size() != vx.size() + 1)
      throw std::logic_error("implicit step: the vertices' incidence lists are not built");
    const size_t first = group_offset_[vg] - codim_begin_;
    const size_t elements = group_offset_[size_t(&el - state_.groups.data())] - codim_begin_;
    const Real share = Real(1) / Real(gamma + 1);
    // Each element's corner share of its normal term, once (as codim_vertex_forces does).
    parallel_for(el.size(), [&](size_t e) {
      element_normal_load_[elements + e] =
          share * (element_load_[elements + e] * normal_columns<Dim>(el.F[e], gamma).transpose());
    });
    parallel_for(vx.size(), [&](size_t v) {
      Vec<Dim> f = Vec<Dim>::Zero();
      Mat<Dim> S = Mat<Dim>::Zero();
      for (uint32_t q = vx.incident_begin[v]; q < vx.incident_begin[v + 1]; ++q) {
        const size_t e = vx.incident[q] / corners, corner = vx.incident[q] % corners;
        f += element_load_[elements + e] *
             tangent_coefficients<Dim>(el.rest_inverse[e], gamma, int(corner));
        S += element_normal_load_[elements + e];
      }
      vertex_f_[first + v] = f;
      vertex_S_[first + v] = S;
    });
  }
}

template <int Dim>
void IncrementalPotential<Dim>::scatter_vertex(size_t k, std::vector<Real>& out) const {
  const size_t c = k - codim_begin_;
  const Vec<Dim> f = dt_ * vertex_f_[c];
  const Mat<Dim> S = dt_ * vertex_S_[c];
  for (int s = 0; s < kStencil; ++s) {
    Eigen::Map<Vec<Dim>> on(&out[size_t(nodes_[k][size_t(s)]) * Dim]);
    on += weights_[c][size_t(s)] * f + S * grads_[k][size_t(s)];
  }
}

template <int Dim>
void IncrementalPotential<Dim>::deformations(const std::vector<Real>& v) {
  if (codim_) {
    gather_vertices(v);
    parallel_for(refs_.size() - codim_begin_, [&](size_t c) {
      const size_t k = codim_begin_ + c;
      if (is_kind(k, GroupKind::MeshVertices))
        vertex_x_[c] = state_.groups[refs_[k].group].x[refs_[k].index] + dt_ * vertex_u_[c];
    });
    parallel_for(elements_.size(), [&](size_t q) {
      const size_t k = elements_[q];
      F_[k] = state_.groups[refs_[k].group].F[refs_[k].index] + dt_ * element_rate(k);
    });
  }
  parallel_for(refs_.size(), [&](size_t k) {
    const ParticleRef& r = refs_[k];
    if (!is_kind(k, GroupKind::Volumetric)) return;
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
    if (p.kind == GroupKind::MeshVertices) return 0.0;  // no volume: their elements' energy
    const size_t i = refs_[k].index;
    const MaterialParams& m = settings_.materials[p.material[i]];
    return double(p.vol0[i]) * double(energy_density<Dim>(m, F_[k], p.fiber_of(i), degradation_[k]));
  });
  double bending = 0;
  for (const Particles<Dim>& el : state_.groups) {
    if (element_dimension(el.kind) == 0 || el.hinges.size() == 0) continue;
    const Vec<Dim>* x = &vertex_x_[group_offset_[size_t(el.vertex_group)] - codim_begin_];
    bending += deterministic_sum<double>(el.hinges.size(), [&](size_t h) {
      return double(hinge_energy(el, h, x));
    });
  }
  return kinetic + elastic + bending;
}

template <int Dim>
void IncrementalPotential<Dim>::gradient(const std::vector<Real>& v, std::vector<Real>& g) {
  deformations(v);
  parallel_for(mass_.size(), [&](size_t node) {
    for (int a = 0; a < Dim; ++a)
      g[node * Dim + a] = mass_[node] * (v[node * Dim + a] - v_star_[node * Dim + a]);
  });
  if (codim_) {
    parallel_for(elements_.size(), [&](size_t q) {
      const size_t k = elements_[q];
      const Particles<Dim>& el = state_.groups[refs_[k].group];
      const size_t i = refs_[k].index;
      element_load_[k - codim_begin_] =
          el.vol0[i] * first_piola<Dim>(settings_.materials[el.material[i]], F_[k], Mat<Dim>::Identity());
    });
    load_vertices();
    load_hinges(false);
  }
  scatter([&](size_t k) {
    if (is_kind(k, GroupKind::MeshVertices)) return scatter_vertex(k, g);
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
    if (p.kind == GroupKind::MeshVertices) return;
    const size_t i = refs_[k].index;
    const MaterialParams& m = settings_.materials[p.material[i]];
    hessian_[k] =
        p.vol0[i] * projected_stress_derivative<Dim>(m, F_[k], p.fiber_of(i), degradation_[k]);
  });
  for (size_t g = 0; g < hinge_hessian_.size(); ++g) {
    const Particles<Dim>& el = state_.groups[g];
    hinge_hessian_[g].clear();
    if (el.hinges.size() == 0 || element_dimension(el.kind) != 1) continue;  // surfaces': constant
    hinge_hessian_[g].resize(el.hinges.size());
    const Vec<Dim>* x = &vertex_x_[group_offset_[size_t(el.vertex_group)] - codim_begin_];
    parallel_for(el.hinges.size(), [&](size_t h) { hinge_hessian_[g][h] = curve_hinge_hessian(el, h, x, true); });
  }
  // The Jacobi diagonal: m_i + dt^2 sum_p u^T A_p(a) u for each component a of node i, where
  // u = F^T grad w and A_p(a) the block of the particle's matrix that e_a u^T meets.
  diag_.assign(mass_.size() * Dim, 0);
  const Real dt2 = dt_ * dt_;
  // dn[a] += dt^2 u^T A(a) u, A(a) the block of A that e_a u^T meets.
  auto add_diagonal = [&](const Vec<Dim>& u, const StressDerivative<Dim>& A, Real* dn) {
    for (int a = 0; a < Dim; ++a) {
      Real sum = 0;
      for (int c = 0; c < Dim; ++c)
        for (int e = 0; e < Dim; ++e) sum += u[c] * u[e] * A(a + Dim * c, a + Dim * e);
      dn[a] += dt2 * sum;
    }
  };
  // A vertex's stencil nodes: the same sum for each incident element, with u = w t_c +
  // N^T grad w / (gamma + 1) its corner's coefficients (the other corners' cross terms left
  // out: a preconditioner's approximation).
  auto vertex_diagonal = [&](size_t k) {
    const Particles<Dim>& vx = state_.groups[refs_[k].group];
    const size_t v = refs_[k].index;
    const size_t c = k - codim_begin_;
    for (const Particles<Dim>& el : state_.groups) {
      if (el.vertex_group != int(refs_[k].group)) continue;
      const int gamma = element_dimension(el.kind);
      const size_t corners = size_t(gamma + 1);
      const size_t elements = group_offset_[size_t(&el - state_.groups.data())];
      for (uint32_t q = vx.incident_begin[v]; q < vx.incident_begin[v + 1]; ++q) {
        const size_t e = vx.incident[q] / corners, corner = vx.incident[q] % corners;
        const StressDerivative<Dim>& A = hessian_[elements + e];
        const Vec<Dim> t = tangent_coefficients<Dim>(el.rest_inverse[e], gamma, int(corner));
        const Mat<Dim> Nt = normal_columns<Dim>(el.F[e], gamma).transpose() / Real(gamma + 1);
        for (int s = 0; s < kStencil; ++s) {
          const Vec<Dim> u = weights_[c][size_t(s)] * t + Nt * grads_[k][size_t(s)];
          add_diagonal(u, A, &diag_[size_t(nodes_[k][size_t(s)]) * Dim]);
        }
      }
      // Its hinges: dt^2 w^2 H(corner a, corner a).
      const auto& H = el.hinges;
      if (H.size() == 0) continue;
      const auto& curves = hinge_hessian_[size_t(&el - state_.groups.data())];
      for (uint32_t q = H.vertex_begin[v]; q < H.vertex_begin[v + 1]; ++q) {
        const uint32_t at = H.incident[q];
        const size_t h = size_t(std::upper_bound(H.begin.begin(), H.begin.end(), at) - H.begin.begin()) - 1;
        const Vec<Dim> d = hinge_hessian_diagonal(el, h, curves.empty() ? nullptr : &curves[h], at - H.begin[h]);
        for (int s = 0; s < kStencil; ++s) {
          const Real w = weights_[c][size_t(s)];
          Real* dn = &diag_[size_t(nodes_[k][size_t(s)]) * Dim];
          for (int a = 0; a < Dim; ++a) dn[a] += dt2 * w * w * d[a];
        }
      }
    }
  };
  scatter([&](size_t k) {
    if (is_kind(k, GroupKind::MeshVertices)) return vertex_diagonal(k);
    const StressDerivative<Dim>& A = hessian_[k];
    for (int s = 0; s < kStencil; ++s) {
      add_diagonal(grads_[k][size_t(s)], A, &diag_[size_t(nodes_[k][size_t(s)]) * Dim]);
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
  if (codim_)
    throw std::logic_error("the assembled Hessian does not take codimensional elements");
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
  if (codim_) {
    gather_vertices(dp);
    parallel_for(elements_.size(), [&](size_t q) {
      const size_t k = elements_[q];
      const Mat<Dim> dF = dt_ * element_rate(k);
      const Vec<Dim * Dim> dP = hessian_[k] * dF.reshaped();
      element_load_[k - codim_begin_] = Eigen::Map<const Mat<Dim>>(dP.data());
    });
    load_vertices();
    load_hinges(true);
  }
  scatter([&](size_t k) {
    if (is_kind(k, GroupKind::MeshVertices)) return scatter_vertex(k, y);
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
