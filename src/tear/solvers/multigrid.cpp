// Geometric multigrid on lattice points (solvers/multigrid.h).
#include "tear/solvers/multigrid.h"

#include "tear/exec/parallel.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace tear {

void sparse_multiply(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
                     const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.resize(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  const int* nnz = A.innerNonZeroPtr();  // null when compressed
  parallel_for(size_t(A.rows()), [&](size_t i) {
    const int begin = outer[i], end = nnz ? begin + nnz[i] : outer[i + 1];
    double s = 0;
    for (int k = begin; k < end; ++k) s += value[k] * x[inner[k]];
    y[Eigen::Index(i)] = s;
  });
}

namespace {

// Floor of p / 2 for any sign.
int half_floor(int p) { return p >= 0 ? p / 2 : -((1 - p) / 2); }

struct LexLess {
  template <class V>
  bool operator()(const V& a, const V& b) const {
    for (int d = 0; d < a.size(); ++d)
      if (a[d] != b[d]) return a[d] < b[d];
    return false;
  }
};

// Rows that are entirely empty (a point whose unknowns reach only constrained directions)
// get a unit diagonal, so that every level is nonsingular there; their right-hand side is zero.
void fill_empty_diagonal(Eigen::SparseMatrix<double, Eigen::RowMajor>* A) {
  std::vector<Eigen::Triplet<double>> unit;
  for (Eigen::Index i = 0; i < A->rows(); ++i) {
    double diag = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(*A, i); it; ++it)
      if (it.col() == i) diag = it.value();
    if (diag == 0) unit.emplace_back(i, i, 1.0);
  }
  if (unit.empty()) return;
  Eigen::SparseMatrix<double, Eigen::RowMajor> U(A->rows(), A->cols());
  U.setFromTriplets(unit.begin(), unit.end());
  *A += U;
}

// Points coloured so that no two of one colour share a matrix entry: by their coordinates
// modulo (reach + 1) along each axis, reach being the largest coordinate distance of an entry.
// Each list in point order.
template <int Dim>
std::vector<std::vector<int>> colour_points(const std::vector<IVec<Dim>>& points, int reach) {
  const int m = reach + 1;
  int colours = 1;
  for (int d = 0; d < Dim; ++d) colours *= m;
  std::vector<std::vector<int>> lists(static_cast<size_t>(colours));
  for (size_t k = 0; k < points.size(); ++k) {
    int c = 0;
    for (int d = Dim - 1; d >= 0; --d) c = c * m + ((points[k][d] % m) + m) % m;
    lists[size_t(c)].push_back(int(k));
  }
  lists.erase(std::remove_if(lists.begin(), lists.end(), [](const auto& l) { return l.empty(); }),
              lists.end());
  return lists;
}

// R A P, coarse row by coarse row in parallel, each row's sums made in a fixed order (R's
// entries, then A's, then P's). A coarse point's entries lie within `window` coarse points of
// it along each axis (A's reach plus the interpolation's, halved: 2 for reach 2 or 3), so a
// small dense accumulator per row holds them.
template <int Dim>
Eigen::SparseMatrix<double, Eigen::RowMajor> galerkin_product(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& R,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& P, const std::vector<IVec<Dim>>& coarse,
    int block, int window) {
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  const int width = 2 * window + 1;
  int slots = block;
  for (int d = 0; d < Dim; ++d) slots *= width;
  const size_t rows = size_t(R.rows());
  std::vector<std::vector<std::pair<int, double>>> entries(rows);
  parallel_for(rows, [&](size_t row) {
    thread_local std::vector<double> acc;
    thread_local std::vector<int> column;  // the coarse unknown of each slot, or -1
    acc.assign(size_t(slots), 0.0);
    column.assign(size_t(slots), -1);
    const IVec<Dim>& centre = coarse[row / size_t(block)];
    for (Matrix::InnerIterator r(R, Eigen::Index(row)); r; ++r)
      for (Matrix::InnerIterator a(A, r.col()); a; ++a) {
        const double ra = r.value() * a.value();
        for (Matrix::InnerIterator p(P, a.col()); p; ++p) {
          const int c = int(p.col());
          const IVec<Dim> off = coarse[size_t(c / block)] - centre;
          int slot = 0;
          for (int d = Dim - 1; d >= 0; --d) slot = slot * width + off[d] + window;
          slot = slot * block + c % block;
          acc[size_t(slot)] += ra * p.value();
          column[size_t(slot)] = c;
        }
      }
    std::vector<std::pair<int, double>>& out = entries[row];
    for (int slot = 0; slot < slots; ++slot)
      if (column[size_t(slot)] >= 0 && acc[size_t(slot)] != 0)
        out.emplace_back(column[size_t(slot)], acc[size_t(slot)]);
    std::sort(out.begin(), out.end());
  });
  std::vector<int> start(rows + 1, 0);
  for (size_t row = 0; row < rows; ++row) start[row + 1] = start[row] + int(entries[row].size());
  Matrix C(R.rows(), P.cols());
  C.resizeNonZeros(start[rows]);
  std::copy(start.begin(), start.end(), C.outerIndexPtr());
  parallel_for(rows, [&](size_t row) {
    int k = start[row];
    for (const auto& [col, value] : entries[row]) {
      C.innerIndexPtr()[k] = col;
      C.valuePtr()[k] = value;
      ++k;
    }
  });
  return C;
}

}  // namespace

template <int Dim>
LatticeMultigrid<Dim>::LatticeMultigrid(const std::vector<IVec<Dim>>& points, int block,
                                        int reach, Matrix&& A,
                                        const std::vector<double>& free,
                                        const MultigridSettings& settings)
    : block_(block), free_(free), settings_(settings) {
  const int B = block;
  if (reach < 1 || reach > 3)
    throw std::invalid_argument("LatticeMultigrid: reach must be 1, 2 or 3");
  // A coarse entry (I, J) comes from fine points i, j with |i - 2I|, |j - 2J| <= 1 and
  // |i - j| <= reach: |I - J| <= (reach + 2) / 2, which is 2 for any fine reach up to 3.
  constexpr int kCoarseReach = 2;
  std::vector<IVec<Dim>> fine = points;
  fill_empty_diagonal(&A);
  // Eigen's sparse matrices have no move constructor: levels are made in place and matrices
  // swapped in.
  levels_.reserve(size_t(settings.max_levels));
  levels_.emplace_back();
  levels_.back().A.swap(A);
  levels_.back().colours = colour_points<Dim>(fine, reach);
  while (levels() < settings.max_levels && levels_.back().A.rows() > settings.coarsest) {
    std::vector<IVec<Dim>> coarse;
    coarse.reserve(fine.size() * 2);
    for (const IVec<Dim>& p : fine) {
      for (int corner = 0; corner < (1 << Dim); ++corner) {
        IVec<Dim> c;
        bool valid = true;
        for (int d = 0; d < Dim; ++d) {
          const bool upper = corner >> d & 1;
          if (p[d] % 2 == 0 && upper) valid = false;
          c[d] = half_floor(p[d]) + (upper ? 1 : 0);
        }
        if (valid) coarse.push_back(c);
      }
    }
    std::sort(coarse.begin(), coarse.end(), LexLess());
    coarse.erase(std::unique(coarse.begin(), coarse.end()), coarse.end());
    if (double(coarse.size()) > 0.9 * double(fine.size())) break;  // no longer coarsening
    // P: fine rows, coarse columns; on the finest level each fine block is the point's free
    // projection times the weight.
    const bool project = levels() == 1 && !free_.empty();
    std::vector<Eigen::Triplet<double>> entries;
    for (size_t k = 0; k < fine.size(); ++k) {
      const IVec<Dim>& p = fine[k];
      for (int corner = 0; corner < (1 << Dim); ++corner) {
        IVec<Dim> c;
        double w = 1;
        bool valid = true;
        for (int d = 0; d < Dim; ++d) {
          const bool upper = corner >> d & 1;
          const bool odd = p[d] % 2 != 0;
          if (!odd && upper) valid = false;
          c[d] = half_floor(p[d]) + (upper ? 1 : 0);
          if (odd) w *= 0.5;
        }
        if (!valid) continue;
        const auto it = std::lower_bound(coarse.begin(), coarse.end(), c, LexLess());
        const int col = int(it - coarse.begin());
        for (int a = 0; a < B; ++a)
          for (int b = 0; b < B; ++b) {
            const double f = project ? free_[(k * size_t(B) + size_t(b)) * size_t(B) + size_t(a)]
                                     : (a == b ? 1.0 : 0.0);
            if (f != 0) entries.emplace_back(int(k) * B + a, col * B + b, w * f);
          }
      }
    }
    Level& l = levels_.back();
    l.P.resize(Eigen::Index(fine.size()) * B, Eigen::Index(coarse.size()) * B);
    l.P.setFromTriplets(entries.begin(), entries.end());
    l.R = l.P.transpose();
    Matrix Ac = galerkin_product<Dim>(l.R, l.A, l.P, coarse, B, kCoarseReach);
    fill_empty_diagonal(&Ac);
    levels_.emplace_back();
    levels_.back().A.swap(Ac);
    levels_.back().colours = colour_points<Dim>(coarse, kCoarseReach);
    fine.swap(coarse);
  }
  for (Level& l : levels_) {
    l.x.resize(l.A.rows());
    l.b.resize(l.A.rows());
    l.r.resize(l.A.rows());
  }
  // The coarsest level, factored; a relative shift of 1e-10 on its diagonal keeps a
  // semi-definite matrix (points whose interpolations coincide) factorable.
  Eigen::SparseMatrix<double> Ac = levels_.back().A;
  for (Eigen::Index i = 0; i < Ac.rows(); ++i) Ac.coeffRef(i, i) *= 1 + 1e-10;
  coarse_.compute(Ac);
  factored_ = coarse_.info() == Eigen::Success && (coarse_.vectorD().array() > 0).all();
}

template <int Dim>
std::vector<long> LatticeMultigrid<Dim>::sizes() const {
  std::vector<long> s;
  for (const Level& l : levels_) s.push_back(long(l.A.rows()));
  return s;
}

template <int Dim>
void LatticeMultigrid<Dim>::smooth(const Level& l, bool forward) const {
  const int B = block_;
  // Gauss-Seidel on one point's rows, in the given order of its components.
  auto relax = [&](int point, bool forward) {
    for (int q = 0; q < B; ++q) {
      const Eigen::Index i = Eigen::Index(point) * B + (forward ? q : B - 1 - q);
      double sum = l.b[i], diag = 0;
      for (typename Matrix::InnerIterator it(l.A, i); it; ++it) {
        if (it.col() == i) {
          diag = it.value();
        } else {
          sum -= it.value() * l.x[it.col()];
        }
      }
      if (diag > 0) l.x[i] = sum / diag;
    }
  };
  auto colour = [&](const std::vector<int>& list, bool forward) {
    if (list.size() < 256) {
      for (int point : list) relax(point, forward);
    } else {
      parallel_for(list.size(), [&](size_t k) { relax(list[k], forward); });
    }
  };
  for (int sweep = 0; sweep < settings_.smoothing; ++sweep) {
    if (forward) {
      for (size_t c = 0; c < l.colours.size(); ++c) colour(l.colours[c], true);
    } else {
      for (size_t c = l.colours.size(); c-- > 0;) colour(l.colours[c], false);
    }
  }
}

template <int Dim>
void LatticeMultigrid<Dim>::cycle(size_t level) const {
  const Level& l = levels_[level];
  if (level + 1 == levels_.size()) {
    if (factored_) {
      l.x = coarse_.solve(l.b);
    } else {  // the factorisation failed: smoothing alone, which is still SPD
      l.x.setZero();
      for (int k = 0; k < 10; ++k) {
        smooth(l, true);
        smooth(l, false);
      }
    }
    return;
  }
  l.x.setZero();
  smooth(l, true);
  sparse_multiply(l.A, l.x, l.r);
  l.r = l.b - l.r;
  const Level& c = levels_[level + 1];
  sparse_multiply(l.R, l.r, c.b);
  cycle(level + 1);
  sparse_multiply(l.P, c.x, l.r);
  l.x += l.r;
  smooth(l, false);
}

template <int Dim>
void LatticeMultigrid<Dim>::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const Level& fine = levels_.front();
  const size_t points = size_t(r.size()) / size_t(block_);
  const int B = block_;
  auto project = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
    if (free_.empty()) {
      out = in;
      return;
    }
    out.resize(in.size());
    parallel_for(points, [&](size_t k) {
      const Eigen::Map<const Eigen::MatrixXd> F(&free_[k * size_t(B * B)], B, B);
      out.segment(Eigen::Index(k) * B, B) = F * in.segment(Eigen::Index(k) * B, B);
    });
  };
  project(r, fine.b);
  cycle(0);
  project(fine.x, z);
}

template class LatticeMultigrid<2>;
template class LatticeMultigrid<3>;

}  // namespace tear
