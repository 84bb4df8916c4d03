#include "tear/fem/fem.h"

#include "tear/exec/parallel.h"
#include "tear/grid/collider.h"
#include "tear/solvers/newton.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#ifdef TEAR_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#include <dlfcn.h>
#endif

#include <algorithm>
#include <cmath>
#include <limits>

namespace tear {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <int Dim>
using ElementHessian = Eigen::Matrix<double, Dim*(Dim + 1), Dim*(Dim + 1)>;

// The corner gradients of the element's linear shape functions at rest: F = sum_a x_a g_a^T.
template <int Dim>
std::array<Vec<Dim>, Dim + 1> shape_gradients(const Mat<Dim>& rest_inverse) {
  std::array<Vec<Dim>, Dim + 1> g;
  g[0] = Vec<Dim>::Zero();
  for (int a = 1; a <= Dim; ++a) {
    g[size_t(a)] = rest_inverse.row(a - 1).transpose();
    g[0] -= g[size_t(a)];
  }
  return g;
}

// An element's edges from its corner 0 at positions x, as columns (D_s; D_m at rest).
template <int Dim>
Mat<Dim> edge_matrix(const typename FemElements<Dim>::Corners& c, const std::vector<Vec<Dim>>& x) {
  Mat<Dim> D;
  for (int a = 1; a <= Dim; ++a) D.col(a - 1) = x[c[size_t(a)]] - x[c[0]];
  return D;
}

template <int Dim>
const MaterialParams& material_of(const MpmSettings& s, const FemState<Dim>& st, size_t e) {
  return s.materials[st.elements.material[e]];
}

// Walls (a node within kWallNodes cells of a domain face, as the MPM grid's wall nodes) and
// colliders at node position p: fn(n, v_wall, type, friction) as NodeContacts::visit.
template <int Dim, class Fn>
void visit_contacts(const MpmSettings& s, const ColliderContacts& colliders, const Vec<Dim>& x,
                    Fn&& fn) {
  if (s.walls != ContactType::None) {
    const double width = kWallNodes * s.dx;
    for (int d = 0; d < Dim; ++d) {
      Vec<Dim> n = Vec<Dim>::Zero();
      if (double(x[d]) < s.domain_min[d] + width)
        n[d] = 1;
      else if (double(x[d]) > s.domain_max[d] - width)
        n[d] = -1;
      else
        continue;
      fn(n, Vec<Dim>::Zero().eval(), s.walls, Real(0));
    }
  }
  if (colliders.empty()) return;
  Vec3d p = Vec3d::Zero();
  p.template head<Dim>() = x.template cast<double>();
  colliders.visit<Dim>(p, fn);
}

template <int Dim>
void apply_node_contacts(const MpmSettings& s, FemState<Dim>* st) {
  const ColliderContacts colliders(s.colliders, st->time);
  Particles<Dim>& p = st->nodes;
  parallel_for(p.size(), [&](size_t i) {
    visit_contacts<Dim>(s, colliders, p.x[i],
                        [&](const Vec<Dim>& n, const Vec<Dim>& vw, ContactType type, Real mu) {
                          p.v[i] = contact_velocity<Dim>(p.v[i], vw, n, type, mu);
                        });
  });
}

}  // namespace

template <int Dim>
ElementHessian<Dim> element_hessian(const MpmSettings& s, const FemState<Dim>& st,
                                    const std::vector<Vec<Dim>>& x, size_t e);

namespace {

// Sum over the (element, corner) pairs of node i in element order: the gather that makes node
// forces the same bits on any thread count.
template <int Dim>
void gather_corners(const FemState<Dim>& st, const std::vector<Vec<Dim>>& corner,
                    std::vector<Vec<Dim>>* out) {
  out->resize(st.num_nodes());
  parallel_for(st.num_nodes(), [&](size_t i) {
    Vec<Dim> sum = Vec<Dim>::Zero();
    for (uint32_t k = st.incident_begin[i]; k < st.incident_begin[i + 1]; ++k)
      sum += corner[st.incident[k]];
    (*out)[i] = sum;
  });
}

// The Rayleigh damping force's negative, (alpha M + beta K(x)) v per node, K from the elements'
// projected Hessians at x (the explicit integrator's; the implicit one assembles the same
// matrix, FemPotential::assemble_damping).
template <int Dim>
void rayleigh_damping(const MpmSettings& s, const FemState<Dim>& st, const std::vector<Vec<Dim>>& x,
                      const std::vector<Vec<Dim>>& v, std::vector<Vec<Dim>>* out) {
  const FemElements<Dim>& el = st.elements;
  std::vector<Vec<Dim>> corner(el.size() * (Dim + 1), Vec<Dim>::Zero());
  parallel_for(el.size(), [&](size_t e) {
    if (el.stiffness_damping[e] == 0) return;
    Eigen::Matrix<double, Dim*(Dim + 1), 1> ve;
    for (int a = 0; a <= Dim; ++a)
      ve.template segment<Dim>(a * Dim) = v[el.corners[e][size_t(a)]].template cast<double>();
    const Eigen::Matrix<double, Dim*(Dim + 1), 1> f =
        double(el.stiffness_damping[e]) * (element_hessian(s, st, x, e) * ve);
    for (int a = 0; a <= Dim; ++a)
      corner[e * (Dim + 1) + size_t(a)] = f.template segment<Dim>(a * Dim).template cast<Real>();
  });
  gather_corners(st, corner, out);
  parallel_for(st.num_nodes(), [&](size_t i) { (*out)[i] += st.mass_damping[i] * v[i]; });
}

template <int Dim>
void explicit_fem_step(const MpmSettings& s, FemState<Dim>* st, double dt) {
  Particles<Dim>& p = st->nodes;
  std::vector<Vec<Dim>> grad;
  fem_elastic_gradient(s, *st, p.x, &grad);
  if (st->damped) {
    std::vector<Vec<Dim>> damping;
    rayleigh_damping(s, *st, p.x, p.v, &damping);
    parallel_for(p.size(), [&](size_t i) { grad[i] += damping[i]; });
  }
  const Vec<Dim> g = s.gravity.head<Dim>().template cast<Real>();
  const Real h = Real(dt);
  parallel_for(p.size(), [&](size_t i) { p.v[i] += h * (g - grad[i] / p.mass[i]); });
  apply_node_contacts(s, st);
  parallel_for(p.size(), [&](size_t i) { p.x[i] += h * p.v[i]; });
}

}  // namespace

namespace fem_detail {

// The implicit matrix's direct factor: CHOLMOD's supernodal Cholesky where tear is built with
// SuiteSparse (its ordering and symbolic analysis once, its numeric factor per Hessian), else
// Eigen's SimplicialLDLT. Both are sequential, so the same matrix gives the same factor on any
// machine and thread count (with the same BLAS library). entries(): the factor's stored values,
// for memory figures.
#ifdef TEAR_HAVE_CHOLMOD
class DirectFactor
    : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  // One thread in OpenBLAS (when that is the BLAS installed) and in the OpenMP regions CHOLMOD
  // and an OpenMP BLAS run (tear itself uses TBB, not OpenMP): a blocked BLAS's sums would
  // otherwise depend on the machine's core count. tear's own threads assemble the matrix; the
  // factor is sequential.
  DirectFactor() {
    using SetThreads = void (*)(int);
    for (const char* name : {"openblas_set_num_threads", "omp_set_num_threads"})
      if (const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, name))) set(1);
  }
  size_t entries() const {
    const cholmod_factor* f = m_cholmodFactor;
    if (!f) return 0;
    return size_t(f->is_super ? f->xsize : f->nzmax);
  }
};
#else
class DirectFactor : public Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  size_t entries() const { return size_t(matrixL().nestedExpression().nonZeros()); }
};
#endif

}  // namespace fem_detail

// The implicit solve's matrix M + dt^2 K over the nodes' Dim unknowns each, with its sparsity
// fixed by the elements (both triangles stored), the place of every element block in it, and
// its direct factor (DirectFactor: its ordering analysed once).
template <int Dim>
class FemAssembly {
 public:
  static constexpr int kCorners = Dim + 1;
  explicit FemAssembly(const FemState<Dim>& st) {
    const Eigen::Index n = Eigen::Index(st.num_nodes() * Dim);
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(st.elements.size() * kCorners * kCorners * Dim * Dim + size_t(n));
    for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(i, i, 0.0);
    for (size_t e = 0; e < st.elements.size(); ++e)
      for (uint32_t a : st.elements.corners[e])
        for (uint32_t b : st.elements.corners[e])
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) t.emplace_back(a * Dim + i, b * Dim + j, 0.0);
    matrix.resize(n, n);
    matrix.setFromTriplets(t.begin(), t.end());
    matrix.makeCompressed();
    // Where each element block's column starts: its Dim rows are consecutive there.
    offset.resize(st.elements.size() * kCorners * kCorners * Dim);
    const auto find = [&](Eigen::Index row, Eigen::Index col) {
      const int* begin = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col];
      const int* end = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col + 1];
      return int(std::lower_bound(begin, end, int(row)) - matrix.innerIndexPtr());
    };
    parallel_for(st.elements.size(), [&](size_t e) {
      const auto& c = st.elements.corners[e];
      for (int a = 0; a < kCorners; ++a)
        for (int b = 0; b < kCorners; ++b)
          for (int j = 0; j < Dim; ++j)
            offset[((e * kCorners + size_t(a)) * kCorners + size_t(b)) * Dim + size_t(j)] =
                find(Eigen::Index(c[size_t(a)]) * Dim, Eigen::Index(c[size_t(b)]) * Dim + j);
    });
    node_block.resize(size_t(n));
    for (Eigen::Index i = 0; i < n; ++i) node_block[size_t(i)] = find(i - i % Dim, i);
  }

  // Where entry (k, k) is: node k / Dim's diagonal block, column k.
  int diagonal(size_t k) const { return node_block[k] + int(k % Dim); }

  Eigen::SparseMatrix<double> matrix;
  // offset: each element block's columns; node_block[i Dim + j]: column j of node i's diagonal
  // block (its Dim rows are consecutive there).
  std::vector<int> offset, node_block;
  // The Rayleigh damping matrix alpha M + beta K(x^n) of the step (damped bodies only), projected
  // to the nodes' free directions, on the matrix's pattern: its values.
  std::vector<double> damping;
  Eigen::VectorXd in, out;  // the solves' buffers
  fem_detail::DirectFactor factor;
  bool analysed = false;
  // The factor's dt (-1: none yet), the CG iterations of the last solve preconditioned by it, and
  // the factorisations so far.
  static constexpr int kRefactorAfter = 8;
  double factored_dt = -1;
  int solve_iterations = 0;
  long factorizations = 0;
};

namespace {

// The consistent mass's difference from the lumped one, C = sum over elements of
// c (1 - (Dim + 1) delta_ab) I (FemElements::mass_coupling): u^T C u / 2 for the nodes'
// vectors u(i), and C u. Per element c (|sum_a u_a|^2 - (Dim + 1) sum_a |u_a|^2) / 2 and
// c (sum_b u_b - (Dim + 1) u_a) at corner a, gathered in element order.
template <int Dim, class U>
double consistent_mass_energy(const FemState<Dim>& st, U&& u) {
  const FemElements<Dim>& el = st.elements;
  return deterministic_sum<double>(el.size(), [&](size_t e) {
    const double c = double(el.mass_coupling[e]);
    if (c == 0) return 0.0;
    Vec<Dim> sum = Vec<Dim>::Zero();
    double squares = 0;
    for (uint32_t k : el.corners[e]) {
      const Vec<Dim> uk = u(k);
      sum += uk;
      squares += double(uk.squaredNorm());
    }
    return 0.5 * c * (double(sum.squaredNorm()) - (Dim + 1) * squares);
  });
}

template <int Dim, class U>
void consistent_mass_times(const FemState<Dim>& st, U&& u, std::vector<Vec<Dim>>* out) {
  const FemElements<Dim>& el = st.elements;
  std::vector<Vec<Dim>> corner(el.size() * (Dim + 1));
  parallel_for(el.size(), [&](size_t e) {
    const Real c = el.mass_coupling[e];
    Vec<Dim> sum = Vec<Dim>::Zero();
    for (uint32_t k : el.corners[e]) sum += u(k);
    for (int a = 0; a <= Dim; ++a)
      corner[e * (Dim + 1) + size_t(a)] = c * (sum - Real(Dim + 1) * u(el.corners[e][size_t(a)]));
  });
  gather_corners(st, corner, out);
}

// The incremental potential of one backward Euler step over the node velocities v (Dim per
// node): sum_i m_i / 2 |v_i - v*_i|^2 (+ (v - v*)^T C (v - v*) / 2 for consistent mass) +
// E(x^n + dt v), with v* = v^n + dt g after contact, and
// each node's velocity held in the directions its boundaries fix (free_directions_at).
// solvers/newton.h's problem; the "preconditioner" is the exact factor (direct) or the diagonal.
template <int Dim>
class FemPotential {
 public:
  FemPotential(const MpmSettings& s, FemState<Dim>& st, Real dt)
      : s_(s), st_(st), dt_(dt), n_(st.num_nodes()) {
    const Particles<Dim>& p = st.nodes;
    const Vec<Dim> g = s.gravity.head<Dim>().template cast<Real>();
    v_star_.resize(n_);
    parallel_for(n_, [&](size_t i) { v_star_[i] = p.v[i] + dt * g; });
    const ColliderContacts colliders(s.colliders, st.time);
    free_.resize(n_);
    parallel_for(n_, [&](size_t i) {
      const auto visit = [&](auto&& fn) { visit_contacts<Dim>(s, colliders, p.x[i], fn); };
      visit([&](const Vec<Dim>& n, const Vec<Dim>& vw, ContactType type, Real mu) {
        v_star_[i] = contact_velocity<Dim>(v_star_[i], vw, n, type, mu);
      });
      free_[i] = free_directions_at<Dim>(visit, v_star_[i]);
    });
    x_.resize(n_);
    grad_.resize(n_);
    if (!st.assembly) st.assembly = std::make_shared<FemAssembly<Dim>>(st);
    // A step starts from a fresh factor: the step's result depends on this state alone, so that a
    // run resumed from a checkpoint takes the same iterations.
    st.assembly->factored_dt = -1;
    direct_ = s.implicit_preconditioner != ImplicitPreconditioner::Jacobi;
    if (st.damped) assemble_damping();
  }

  std::vector<Real> initial() const {
    std::vector<Real> v(n_ * Dim);
    for (size_t i = 0; i < n_; ++i) std::copy_n(v_star_[i].data(), Dim, &v[i * Dim]);
    return v;
  }

  void positions(const std::vector<Real>& v) {
    const Particles<Dim>& p = st_.nodes;
    parallel_for(n_, [&](size_t i) {
      x_[i] = p.x[i] + dt_ * Eigen::Map<const Vec<Dim>>(&v[i * Dim]);
    });
  }

  double energy(const std::vector<Real>& v) {
    positions(v);
    const Particles<Dim>& p = st_.nodes;
    const double kinetic = deterministic_sum<double>(n_, [&](size_t i) {
      return 0.5 * double(p.mass[i]) * double(dv(v, i).squaredNorm());
    });
    double damping = 0;
    if (st_.damped) {
      const Eigen::Map<const Eigen::VectorXd> vv(v.data(), Eigen::Index(v.size()));
      damping = 0.5 * double(dt_) * vv.dot(damping_matrix() * vv);
    }
    const double consistent =
        st_.consistent ? consistent_mass_energy(st_, [&](size_t i) { return dv(v, i); }) : 0.0;
    return kinetic + consistent + fem_elastic_energy(s_, st_, x_) + damping;
  }

  void gradient(const std::vector<Real>& v, std::vector<Real>& g) {
    node_gradient(v);
    parallel_for(n_, [&](size_t i) {
      Eigen::Map<Vec<Dim>> out(&g[i * Dim]);
      out = free_[i] * grad_[i];
    });
    if (st_.damped) {  // dt D v, D projected already
      FemAssembly<Dim>& A = *st_.assembly;
      A.out = damping_matrix() * Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
      for (size_t k = 0; k < g.size(); ++k) g[k] += dt_ * A.out[Eigen::Index(k)];
    }
  }

  // The largest velocity change a node still needs, as a distance moved in a step over the
  // length scale dx (the MPM integrator's measure, docs/fem.md).
  double residual(const std::vector<Real>& g) const {
    const Particles<Dim>& p = st_.nodes;
    const Real worst = parallel_max<Real>(
        n_, [&](size_t i) { return Eigen::Map<const Vec<Dim>>(&g[i * Dim]).norm() / p.mass[i]; },
        Real(0));
    return double(worst) * double(dt_) / s_.dx;
  }

  void prepare_hessian(const std::vector<Real>& v) {
    positions(v);
    FemAssembly<Dim>& A = *st_.assembly;
    double* values = A.matrix.valuePtr();
    std::fill(values, values + A.matrix.nonZeros(), 0.0);
    add_element_blocks(double(dt_) * double(dt_), [](size_t) { return 1.0; }, values);
    if (st_.consistent) add_consistent_mass(values);
    const Particles<Dim>& p = st_.nodes;
    for (size_t i = 0; i < n_; ++i) {
      // The fixed directions: the identity (they are not unknowns; it keeps the factor
      // definite).
      add_node_block(i, Mat<Dim>::Identity() - free_[i], values);
      for (int a = 0; a < Dim; ++a) values[A.diagonal(i * Dim + size_t(a))] += double(p.mass[i]);
    }
    if (st_.damped)
      for (size_t k = 0; k < A.damping.size(); ++k) values[k] += double(dt_) * A.damping[k];
    // The factor of an earlier Hessian of this step stays the preconditioner while CG converges
    // with it in a few iterations: refactored at the step's first solve and after a solve that
    // took more than kRefactorAfter iterations.
    if (direct_) {
      if (!A.analysed) {
        A.factor.analyzePattern(A.matrix);
        A.analysed = true;
      }
      if (A.factored_dt != double(dt_) || A.solve_iterations > FemAssembly<Dim>::kRefactorAfter) {
        A.factor.factorize(A.matrix);
        A.factored_dt = double(dt_);
        ++A.factorizations;
      }
      A.solve_iterations = -1;  // precondition() counts this solve's iterations
    }
  }

  void apply_hessian(const std::vector<Real>& d, std::vector<Real>& y) {
    FemAssembly<Dim>& A = *st_.assembly;
    A.in.resize(Eigen::Index(d.size()));
    for (size_t k = 0; k < d.size(); ++k) A.in[Eigen::Index(k)] = double(d[k]);
    A.out = A.matrix * A.in;
    parallel_for(n_, [&](size_t i) {
      Vec<Dim> yi, di;
      for (int a = 0; a < Dim; ++a) {
        yi[a] = Real(A.out[Eigen::Index(i * Dim) + a]);
        di[a] = d[i * Dim + size_t(a)];
      }
      Eigen::Map<Vec<Dim>> out(&y[i * Dim]);
      out = free_[i] * (yi - (Mat<Dim>::Identity() - free_[i]) * di);
    });
  }

  void precondition(const std::vector<Real>& r, std::vector<Real>& z) {
    FemAssembly<Dim>& A = *st_.assembly;
    if (direct_) {
      ++A.solve_iterations;
      A.in.resize(Eigen::Index(r.size()));
      for (size_t k = 0; k < r.size(); ++k) A.in[Eigen::Index(k)] = double(r[k]);
      A.out = A.factor.solve(A.in);
      for (size_t k = 0; k < z.size(); ++k) z[k] = Real(A.out[Eigen::Index(k)]);
    } else {
      for (size_t k = 0; k < z.size(); ++k) z[k] = Real(r[k] / A.matrix.valuePtr()[A.diagonal(k)]);
    }
    parallel_for(n_, [&](size_t i) {
      Eigen::Map<Vec<Dim>> zi(&z[i * Dim]);
      zi = free_[i] * Vec<Dim>(zi);
    });
  }

  bool active(size_t) const { return true; }

  // Coulomb friction from the boundaries' reactions at the solution v: the impulse J that holds
  // a node's fixed directions is the potential's unprojected gradient there (m (v - v*) - dt f),
  // so a node pressed onto a frictional boundary (J . n > 0) loses up to mu J . n / m of its
  // tangential speed relative to it. The friction of the node's own weight was taken from v*
  // already (its normal velocity removed there); this is the weight the elements press it with,
  // which the solve's constraint carries. Without it a body slides on friction held by its
  // contact nodes' own mass alone.
  void apply_reaction_friction(std::vector<Real>* v) {
    node_gradient(*v);
    const Particles<Dim>& p = st_.nodes;
    const ColliderContacts colliders(s_.colliders, st_.time);
    parallel_for(n_, [&](size_t i) {
      Eigen::Map<Vec<Dim>> vi(&(*v)[i * Dim]);
      const Vec<Dim>& J = grad_[i];
      visit_contacts<Dim>(s_, colliders, p.x[i],
                          [&](const Vec<Dim>& n, const Vec<Dim>& vw, ContactType type, Real mu) {
                            if (!(mu > 0) || type == ContactType::Sticky) return;
                            const Real push = n.dot(J);
                            if (!(push > 0)) return;
                            const Vec<Dim> rel = Vec<Dim>(vi) - vw;
                            const Vec<Dim> vt = rel - n.dot(rel) * n;
                            const Real t = vt.norm();
                            if (t > 0) vi -= std::min(t, mu * push / p.mass[i]) / t * vt;
                          });
    });
  }

 private:
  // Node i's velocity change from v*.
  Vec<Dim> dv(const std::vector<Real>& v, size_t i) const {
    return Eigen::Map<const Vec<Dim>>(&v[i * Dim]) - v_star_[i];
  }

  // grad_ = the potential's gradient at v before the boundaries' projection and without the
  // damping term: m (v - v*) + dt dE/dx (+ C (v - v*)) per node.
  void node_gradient(const std::vector<Real>& v) {
    positions(v);
    fem_elastic_gradient(s_, st_, x_, &grad_);
    if (st_.consistent)
      consistent_mass_times(st_, [&](size_t i) { return dv(v, i); }, &mass_times_);
    const Particles<Dim>& p = st_.nodes;
    parallel_for(n_, [&](size_t i) {
      Vec<Dim> gi = p.mass[i] * dv(v, i) + dt_ * grad_[i];
      if (st_.consistent) gi += mass_times_[i];
      grad_[i] = gi;
    });
  }

  // values += scale(e) * weight * the elements' Hessians at x_, each block projected to its
  // nodes' free directions, added in element order (the same sums every time).
  template <class Scale>
  void add_element_blocks(double weight, Scale&& scale, double* values) {
    const FemElements<Dim>& el = st_.elements;
    constexpr int kC = Dim + 1;
    h_.resize(el.size());
    parallel_for(el.size(), [&](size_t e) {
      if (scale(e) != 0) h_[e] = element_hessian(s_, st_, x_, e);
    });
    for (size_t e = 0; e < el.size(); ++e) {
      const double w = weight * scale(e);
      if (w == 0) continue;
      for (int a = 0; a < kC; ++a)
        for (int b = 0; b < kC; ++b)
          add_block(e, a, b, w, h_[e].template block<Dim, Dim>(a * Dim, b * Dim).template cast<Real>(),
                    values);
    }
  }

  // values += the consistent mass's difference from the lumped one, c (1 - (Dim + 1) delta_ab) I
  // per element (zero row sums: the lumped diagonal the nodes' masses put in stays), projected.
  void add_consistent_mass(double* values) {
    const FemElements<Dim>& el = st_.elements;
    for (size_t e = 0; e < el.size(); ++e) {
      const double c = double(el.mass_coupling[e]);
      if (c == 0) continue;
      for (int a = 0; a <= Dim; ++a)
        for (int b = 0; b <= Dim; ++b)
          add_block(e, a, b, a == b ? -Dim * c : c, Mat<Dim>::Identity(), values);
    }
  }

  // values += w P_a B P_b in element e's block (a, b), P the corners' free directions.
  void add_block(size_t e, int a, int b, double w, const Mat<Dim>& B, double* values) const {
    const FemAssembly<Dim>& A = *st_.assembly;
    constexpr int kC = Dim + 1;
    const auto& c = st_.elements.corners[e];
    const Mat<Dim> block = free_[c[size_t(a)]] * B * free_[c[size_t(b)]];
    for (int j = 0; j < Dim; ++j) {
      double* col = values + A.offset[((e * kC + size_t(a)) * kC + size_t(b)) * Dim + size_t(j)];
      for (int i = 0; i < Dim; ++i) col[i] += w * double(block(i, j));
    }
  }

  // values += B in node i's diagonal block.
  void add_node_block(size_t i, const Mat<Dim>& B, double* values) {
    const FemAssembly<Dim>& A = *st_.assembly;
    for (int j = 0; j < Dim; ++j) {
      double* col = values + A.node_block[i * Dim + size_t(j)];
      for (int a = 0; a < Dim; ++a) col[a] += double(B(a, j));
    }
  }

  // The step's damping matrix alpha M + beta K(x^n), projected to the free directions, so that
  // the potential's damping term dt/2 v^T D v has the gradient dt D v in the free directions.
  void assemble_damping() {
    FemAssembly<Dim>& A = *st_.assembly;
    A.damping.assign(size_t(A.matrix.nonZeros()), 0.0);
    x_ = st_.nodes.x;
    const FemElements<Dim>& el = st_.elements;
    add_element_blocks(1.0, [&](size_t e) { return double(el.stiffness_damping[e]); },
                       A.damping.data());
    for (size_t i = 0; i < n_; ++i)
      add_node_block(i, st_.mass_damping[i] * free_[i], A.damping.data());
  }

  Eigen::Map<const Eigen::SparseMatrix<double>> damping_matrix() const {
    const FemAssembly<Dim>& A = *st_.assembly;
    return {A.matrix.rows(), A.matrix.cols(), A.matrix.nonZeros(), A.matrix.outerIndexPtr(),
            A.matrix.innerIndexPtr(), A.damping.data()};
  }

  const MpmSettings& s_;
  FemState<Dim>& st_;
  Real dt_;
  size_t n_;
  bool direct_ = true;
  std::vector<Vec<Dim>> v_star_, x_, grad_, mass_times_;
  std::vector<Mat<Dim>> free_;
  std::vector<ElementHessian<Dim>, Eigen::aligned_allocator<ElementHessian<Dim>>> h_;
};

template <int Dim>
void implicit_fem_step(const MpmSettings& s, FemState<Dim>* st, double dt, FemSolveStats* stats) {
  FemPotential<Dim> potential(s, *st, Real(dt));
  std::vector<Real> v = potential.initial();
  NewtonSettings ns = s.newton;
  if (s.implicit_preconditioner != ImplicitPreconditioner::Jacobi) ns.cg_escalate_after = 0;
  const NewtonResult r = newton_minimize(potential, &v, ns);
  bool friction = false;
  for (const Collider& c : s.colliders) friction = friction || c.friction > 0;
  if (friction) potential.apply_reaction_friction(&v);
  Particles<Dim>& p = st->nodes;
  parallel_for(p.size(), [&](size_t i) { p.v[i] = Eigen::Map<const Vec<Dim>>(&v[i * Dim]); });
  apply_node_contacts(s, st);  // friction on the solved velocities
  const Real h = Real(dt);
  parallel_for(p.size(), [&](size_t i) { p.x[i] += h * p.v[i]; });
  if (stats) {
    ++stats->solves;
    stats->newton_iterations += r.iterations;
    stats->newton_iterations_max = std::max(stats->newton_iterations_max, r.iterations);
    stats->cg_iterations += r.cg_iterations;
    stats->residual_max = std::max(stats->residual_max, r.residual);
    if (!r.converged) ++stats->unconverged;
  }
}

}  // namespace

template <int Dim>
void append_fem_body(const FemMesh& mesh, const std::vector<MaterialParams>& materials,
                     const std::function<ElementSetup<Dim>(const Vec3d&, size_t)>& setup,
                     const Vec3d& velocity, const Vec3d& angular_velocity, const Vec3d& centre,
                     FemState<Dim>* st) {
  FemBody body;
  Particles<Dim>& p = st->nodes;
  body.node_begin = p.size();
  body.element_begin = st->elements.size();
  body.face_begin = st->faces.size();
  const uint32_t base = uint32_t(p.size());
  for (const Vec3d& x : mesh.nodes) {
    const Vec3d w = Dim == 2 ? Vec3d(0, 0, angular_velocity.z()) : angular_velocity;
    const Vec3d v = velocity + w.cross(x - centre);
    p.push_back(x.head<Dim>().template cast<Real>(), v.head<Dim>().template cast<Real>(),
                Mat<Dim>::Identity(), Real(0), Real(0), 0);
  }
  std::vector<bool> named(mesh.nodes.size(), false);
  st->mass_damping.resize(p.size(), Real(0));
  FemElements<Dim>& el = st->elements;
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    typename FemElements<Dim>::Corners c;
    Vec3d centroid = Vec3d::Zero();
    for (int a = 0; a <= Dim; ++a) {
      c[size_t(a)] = base + uint32_t(mesh.elements[e][size_t(a)]);
      centroid += mesh.nodes[size_t(mesh.elements[e][size_t(a)])] / (Dim + 1);
    }
    const Mat<Dim> Dm = edge_matrix<Dim>(c, p.x);
    const double volume = element_volume(mesh, e);
    const ElementSetup<Dim> made = setup(centroid, e);
    el.corners.push_back(c);
    el.rest_inverse.push_back(Dm.inverse());
    el.vol0.push_back(Real(volume));
    el.material.push_back(made.material);
    el.fiber.push_back(made.fiber);
    el.stiffness_damping.push_back(made.stiffness_damping);
    el.plastic.emplace_back();
    el.mass_coupling.push_back(
        made.consistent_mass
            ? Real(materials[made.material].rho * volume / ((Dim + 1) * (Dim + 2)))
            : Real(0));
    st->consistent = st->consistent || made.consistent_mass;
    st->damped = st->damped || made.mass_damping > 0 || made.stiffness_damping > 0;
    st->stiffness_damping_max = std::max(st->stiffness_damping_max, made.stiffness_damping);
    for (uint32_t k : c) {
      const Real share = Real(materials[made.material].rho * volume / (Dim + 1));
      p.mass[k] += share;
      st->mass_damping[k] += made.mass_damping * share;
      if (!named[k - base]) p.material[k] = made.material, named[k - base] = true;
    }
  }
  for (std::array<int, 3> f : boundary_faces(mesh)) {
    for (int& k : f)
      if (k >= 0) k += int(base);
    st->faces.push_back(f);
  }
  for (size_t i = body.node_begin; i < p.size(); ++i)
    st->mass_damping_rate_max = std::max(st->mass_damping_rate_max, st->mass_damping[i] / p.mass[i]);
  body.node_end = p.size();
  body.element_end = el.size();
  body.face_end = st->faces.size();
  body.figures = mesh_figures(mesh);
  st->bodies.push_back(body);
  const double h = body.figures.smallest_height;
  st->smallest_height = st->bodies.size() == 1 ? h : std::min(st->smallest_height, h);
  // Incidence, rebuilt over all bodies.
  st->incident_begin.assign(p.size() + 1, 0);
  for (const auto& cs : el.corners)
    for (uint32_t k : cs) ++st->incident_begin[k + 1];
  for (size_t i = 0; i < p.size(); ++i) st->incident_begin[i + 1] += st->incident_begin[i];
  st->incident.resize(el.size() * (Dim + 1));
  std::vector<uint32_t> fill(st->incident_begin.begin(), st->incident_begin.end() - 1);
  for (size_t e = 0; e < el.size(); ++e)
    for (int a = 0; a <= Dim; ++a)
      st->incident[fill[el.corners[e][size_t(a)]]++] = uint32_t(e * (Dim + 1) + size_t(a));
  st->assembly.reset();
}

template <int Dim>
Mat<Dim> fem_deformation(const FemState<Dim>& st, const std::vector<Vec<Dim>>& x, size_t e) {
  return edge_matrix<Dim>(st.elements.corners[e], x) * st.elements.rest_inverse[e];
}

template <int Dim>
double fem_elastic_energy(const MpmSettings& s, const FemState<Dim>& st,
                          const std::vector<Vec<Dim>>& x) {
  const FemElements<Dim>& el = st.elements;
  return deterministic_sum<double>(el.size(), [&](size_t e) {
    return double(el.vol0[e]) * double(energy_density<Dim>(material_of(s, st, e),
                                                            fem_deformation(st, x, e), el.fiber[e]));
  });
}

template <int Dim>
void fem_elastic_gradient(const MpmSettings& s, const FemState<Dim>& st,
                          const std::vector<Vec<Dim>>& x, std::vector<Vec<Dim>>* gradient) {
  const FemElements<Dim>& el = st.elements;
  // Each element's corner forces, then each node's sum over its elements in element order.
  std::vector<Vec<Dim>> corner(el.size() * (Dim + 1));
  parallel_for(el.size(), [&](size_t e) {
    const Mat<Dim> P = first_piola<Dim>(material_of(s, st, e), fem_deformation(st, x, e),
                                        el.fiber[e]);
    const auto g = shape_gradients<Dim>(el.rest_inverse[e]);
    for (int a = 0; a <= Dim; ++a) corner[e * (Dim + 1) + size_t(a)] = el.vol0[e] * (P * g[size_t(a)]);
  });
  gather_corners(st, corner, gradient);
}

template <int Dim>
ElementHessian<Dim> element_hessian(const MpmSettings& s, const FemState<Dim>& st,
                                    const std::vector<Vec<Dim>>& x, size_t e) {
  const FemElements<Dim>& el = st.elements;
  const StressDerivative<Dim> A = projected_stress_derivative<Dim>(
      material_of(s, st, e), fem_deformation(st, x, e), el.fiber[e]);
  const auto g = shape_gradients<Dim>(el.rest_inverse[e]);
  // vec(dF) = G dx: column block a is g_a (x) I; H = V G^T A G, with (A G) formed a block of Dim
  // columns at a time.
  Eigen::Matrix<double, Dim * Dim, Dim*(Dim + 1)> G = decltype(G)::Zero();
  for (int a = 0; a <= Dim; ++a)
    for (int j = 0; j < Dim; ++j)
      for (int i = 0; i < Dim; ++i) G(i + Dim * j, a * Dim + i) = double(g[size_t(a)][j]);
  const Eigen::Matrix<double, Dim * Dim, Dim*(Dim + 1)> AG = A.template cast<double>() * G;
  return double(el.vol0[e]) * (G.transpose() * AG);
}

template <int Dim>
Eigen::MatrixXd fem_element_hessian(const MpmSettings& s, const FemState<Dim>& st,
                                    const std::vector<Vec<Dim>>& x, size_t e) {
  return element_hessian(s, st, x, e);
}

template <int Dim>
DtLimits fem_dt_limits(const MpmSettings& s, const FemState<Dim>& st) {
  DtLimits l;
  l.max_dt = s.max_dt;
  l.damage = l.damage_cracking = kInf;
  double c = 0;
  for (const MaterialParams& m : s.materials) c = std::max(c, double(wave_speed(m)));
  const double h = st.smallest_height;
  l.wave = s.integrator == Integrator::Explicit && c > 0 ? s.cfl * h / c : kInf;
  const Particles<Dim>& p = st.nodes;
  if (st.damped && std::isfinite(l.wave)) {
    // Symplectic Euler with the damping force at v^n is stable for dt omega <= 2 (sqrt(1 +
    // zeta^2) - zeta), zeta = (alpha / omega + beta omega) / 2 the highest mode's damping ratio,
    // omega = 2 c / h (docs/fem.md).
    const double beta = double(st.stiffness_damping_max);
    const double alpha = double(st.mass_damping_rate_max);
    const double zeta = beta * c / h + alpha * h / (4 * c);
    l.wave *= std::sqrt(1 + zeta * zeta) - zeta;
  }
  const Real v2 = parallel_max<Real>(p.size(), [&](size_t i) { return p.v[i].squaredNorm(); }, 0);
  // Nodes move at most cfl dx a step: contact is resolved at dx (the walls are kWallNodes dx
  // thick), and the elements themselves do not need it (the implicit solve moves nodes as far as
  // it likes; the explicit wave limit is far shorter). A sliver's height would stall a falling
  // body's steps for nothing.
  l.velocity = v2 > 0 ? s.cfl * s.dx / std::sqrt(double(v2)) : kInf;
  return l;
}

bool fem_plastic(const MpmSettings& s) {
  for (const PlasticParams& p : s.material_plasticity)
    if (p.surface != YieldSurface::None) return true;
  return false;
}

template <int Dim>
size_t fem_plastic_flow(const MpmSettings& s, FemState<Dim>* st) {
  if (!fem_plastic(s)) return 0;
  FemElements<Dim>& el = st->elements;
  const std::vector<Vec<Dim>>& x = st->nodes.x;
  return deterministic_sum<size_t>(el.size(), [&](size_t e) -> size_t {
    const PlasticParams& pp = s.material_plasticity[el.material[e]];
    if (pp.surface == YieldSurface::None) return 0;
    const Mat<Dim> Ds = edge_matrix<Dim>(el.corners[e], x);
    Mat<Dim> F = Ds * el.rest_inverse[e];
    PlasticState state = el.plastic[e];
    if (!return_map(pp, &F, &state)) return 0;
    // A flat element (D_s singular) keeps its rest shape until it opens again.
    const Mat<Dim> rest = Ds.inverse() * F;
    if (!rest.allFinite()) return 0;
    el.rest_inverse[e] = rest;
    el.plastic[e] = state;
    return 1;
  });
}

template <int Dim>
double fem_step(const MpmSettings& s, FemState<Dim>* st, double dt, FemSolveStats* stats) {
  if (s.integrator == Integrator::Implicit) {
    implicit_fem_step(s, st, dt, stats);
  } else {
    if (st->consistent)
      throw std::invalid_argument("consistent mass needs the implicit integrator");
    explicit_fem_step(s, st, dt);
  }
  fem_plastic_flow(s, st);
  st->time += dt;
  ++st->steps;
  return dt;
}

template <int Dim>
FemFigures measure_fem(const MpmSettings& s, const FemState<Dim>& st) {
  const Particles<Dim>& p = st.nodes;
  FemFigures f;
  struct Sums {
    double m = 0, ke = 0;
    Vec3d mom = Vec3d::Zero(), am = Vec3d::Zero();
    Sums& operator+=(const Sums& o) {
      m += o.m, ke += o.ke, mom += o.mom, am += o.am;
      return *this;
    }
  };
  const Sums sums = deterministic_sum<Sums>(p.size(), [&](size_t i) {
    Vec3d x = Vec3d::Zero(), v = Vec3d::Zero();
    x.head<Dim>() = p.x[i].template cast<double>();
    v.head<Dim>() = p.v[i].template cast<double>();
    const double m = double(p.mass[i]);
    return Sums{m, 0.5 * m * v.squaredNorm(), m * v, m * x.cross(v)};
  });
  f.mass = sums.m;
  // Consistent mass: 1/2 v^T M v with the elements' mass matrices (the lumped sum's correction).
  f.kinetic_energy = sums.ke;
  if (st.consistent) f.kinetic_energy += consistent_mass_energy(st, [&](size_t i) {
    return Vec<Dim>(p.v[i]);
  });
  f.momentum = sums.mom;
  f.angular_momentum = sums.am;
  f.elastic_energy = fem_elastic_energy(s, st, p.x);
  return f;
}

template <int Dim>
FemElementFigures fem_element_figures(const MpmSettings& s, const FemState<Dim>& st) {
  const FemElements<Dim>& el = st.elements;
  FemElementFigures f;
  f.energy.resize(el.size());
  f.von_mises.resize(el.size());
  f.J.resize(el.size());
  f.fiber.resize(el.size());
  f.plastic_strain.resize(el.size());
  parallel_for(el.size(), [&](size_t e) {
    f.plastic_strain[e] = double(el.plastic[e].strain);
    const MaterialParams& m = material_of(s, st, e);
    const Mat<Dim> F = fem_deformation(st, st.nodes.x, e);
    const double J = double(F.determinant());
    f.energy[e] = double(energy_density<Dim>(m, F, el.fiber[e]));
    f.J[e] = J;
    f.von_mises[e] = 0;
    if (J > 0) {
      Mat<3> sigma = Mat<3>::Zero();
      sigma.template topLeftCorner<Dim, Dim>() =
          first_piola<Dim>(m, F, el.fiber[e]) * F.transpose() / Real(J);
      const Mat<3> dev = sigma - sigma.trace() / 3 * Mat<3>::Identity();
      f.von_mises[e] = std::sqrt(1.5 * double(dev.squaredNorm()));
    }
    const Vec<Dim> a = F * el.fiber[e].col(0);
    Vec3d dir = Vec3d::Zero();
    if (a.norm() > 0) dir.head<Dim>() = (a / a.norm()).template cast<double>();
    f.fiber[e] = dir;
  });
  return f;
}

template <int Dim>
long find_fem_fault(const MpmSettings& s, const FemState<Dim>& st) {
  const Particles<Dim>& p = st.nodes;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!p.x[i].allFinite() || !p.v[i].allFinite()) return long(i);
    for (int d = 0; d < Dim; ++d)
      if (double(p.x[i][d]) < s.domain_min[d] || double(p.x[i][d]) > s.domain_max[d])
        return long(i);
  }
  return -1;
}

template <int Dim>
size_t fem_memory_bytes(const FemState<Dim>& st) {
  const FemElements<Dim>& el = st.elements;
  size_t bytes = st.nodes.memory_bytes();
  bytes += el.size() * (sizeof(typename FemElements<Dim>::Corners) + 2 * sizeof(Mat<Dim>) +
                        3 * sizeof(Real) + sizeof(uint16_t) + sizeof(PlasticState));
  bytes += st.mass_damping.size() * sizeof(Real);
  bytes += st.incident.size() * sizeof(uint32_t) + st.faces.size() * sizeof(st.faces[0]);
  if (st.assembly) {
    const FemAssembly<Dim>& a = *st.assembly;
    bytes += size_t(a.matrix.nonZeros()) * (sizeof(double) + sizeof(int)) +
             (a.offset.size() + a.node_block.size()) * sizeof(int) +
             a.damping.size() * sizeof(double);
    if (a.analysed) bytes += a.factor.entries() * 12;
  }
  return bytes;
}

#define TEAR_FEM(D)                                                                               \
  template class FemAssembly<D>;                                                                  \
  template void append_fem_body<D>(const FemMesh&, const std::vector<MaterialParams>&,            \
                                   const std::function<ElementSetup<D>(const Vec3d&, size_t)>&,   \
                                   const Vec3d&, const Vec3d&, const Vec3d&, FemState<D>*);       \
  template Mat<D> fem_deformation<D>(const FemState<D>&, const std::vector<Vec<D>>&, size_t);     \
  template double fem_elastic_energy<D>(const MpmSettings&, const FemState<D>&,                   \
                                        const std::vector<Vec<D>>&);                              \
  template void fem_elastic_gradient<D>(const MpmSettings&, const FemState<D>&,                   \
                                        const std::vector<Vec<D>>&, std::vector<Vec<D>>*);        \
  template Eigen::MatrixXd fem_element_hessian<D>(const MpmSettings&, const FemState<D>&,         \
                                                  const std::vector<Vec<D>>&, size_t);            \
  template DtLimits fem_dt_limits<D>(const MpmSettings&, const FemState<D>&);                     \
  template double fem_step<D>(const MpmSettings&, FemState<D>*, double, FemSolveStats*);          \
  template FemFigures measure_fem<D>(const MpmSettings&, const FemState<D>&);                     \
  template long find_fem_fault<D>(const MpmSettings&, const FemState<D>&);                      \
  template FemElementFigures fem_element_figures<D>(const MpmSettings&, const FemState<D>&);    \
  template size_t fem_memory_bytes<D>(const FemState<D>&);                                   \
  template size_t fem_plastic_flow<D>(const MpmSettings&, FemState<D>*);
TEAR_FEM(2)
TEAR_FEM(3)

}  // namespace tear
