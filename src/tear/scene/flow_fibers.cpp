#include "tear/scene/flow_fibers.h"

#include "tear/exec/parallel.h"
#include "tear/solvers/pcg.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tear {

namespace {

std::string point_text(const Vec3d& p, int dim) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y();
  if (dim == 3) s << ", " << p.z();
  s << ")";
  return s.str();
}

}  // namespace

FlowField::FlowField(const Shape& shape, int dim, double h, const std::vector<Vec3d>& sources,
                     const std::vector<Vec3d>& sinks, double radius)
    : dim_(dim), h_(h), sources_(sources), sinks_(sinks), radius_(radius) {
  Vec3d lo, hi;
  shape.bounds(&lo, &hi);
  lo_ = lo - Vec3d::Constant(h);
  for (int d = 0; d < dim; ++d) n_[d] = int(std::ceil((hi[d] - lo[d]) / h)) + 2;
  const size_t cells = size_t(n_[0]) * size_t(n_[1]) * size_t(n_[2]);
  auto centre = [&](size_t c) {
    Vec3d x = lo_ + h * Vec3d(double(c % size_t(n_[0])) + 0.5,
                              double(c / size_t(n_[0]) % size_t(n_[1])) + 0.5,
                              double(c / size_t(n_[0]) / size_t(n_[1])) + 0.5);
    if (dim == 2) x.z() = 0;
    return x;
  };
  inside_.assign(cells, 0);
  parallel_for(cells, [&](size_t c) { inside_[c] = shape.inside(centre(c)) ? 1 : 0; });

  // Held cells: 1 near a source, 0 near a sink (a sink wins where both reach).
  std::vector<double> held(cells, std::numeric_limits<double>::quiet_NaN());
  auto hold = [&](const std::vector<Vec3d>& points, double value, const char* what) {
    for (size_t k = 0; k < points.size(); ++k) {
      size_t count = 0;
      for (size_t c = 0; c < cells; ++c)
        if (inside_[c] && (centre(c) - points[k]).norm() <= radius) held[c] = value, ++count;
      if (count == 0)
        throw std::runtime_error(std::string(what) + " " + std::to_string(k) + " " +
                                 point_text(points[k], dim) + " is not within " +
                                 std::to_string(radius) + " of the shape's inside");
    }
  };
  hold(sources, 1.0, "source");
  hold(sinks, 0.0, "sink");

  // Neighbours across faces.
  const long stride[3] = {1, n_[0], long(n_[0]) * n_[1]};
  auto neighbours = [&](size_t c, auto&& fn) {
    const long ci[3] = {long(c % size_t(n_[0])), long(c / size_t(n_[0]) % size_t(n_[1])),
                        long(c / size_t(n_[0]) / size_t(n_[1]))};
    for (int d = 0; d < dim; ++d)
      for (int s : {-1, 1}) {
        const long j = ci[d] + s;
        if (j < 0 || j >= n_[d]) continue;
        const size_t nb = size_t(long(c) + s * stride[d]);
        if (inside_[nb]) fn(nb);
      }
  };
  // Cells that reach a held cell: the others (cut off) get no potential.
  std::vector<char> reached(cells, 0);
  std::vector<size_t> queue;
  for (size_t c = 0; c < cells; ++c)
    if (inside_[c] && !std::isnan(held[c])) reached[c] = 1, queue.push_back(c);
  while (!queue.empty()) {
    const size_t c = queue.back();
    queue.pop_back();
    neighbours(c, [&](size_t nb) {
      if (!reached[nb]) reached[nb] = 1, queue.push_back(nb);
    });
  }
  // Laplace: sum over inside neighbours (phi_n - phi_c) = 0 at free cells; no-flux boundary
  // (an outside neighbour adds nothing). Held values move to the right-hand side.
  std::vector<Real> b(cells, 0), inv_diag(cells, 0), x(cells, 0);
  for (size_t c = 0; c < cells; ++c) {
    if (!inside_[c] || !reached[c]) continue;
    if (!std::isnan(held[c])) {
      x[c] = Real(held[c]);
      continue;
    }
    int degree = 0;
    double rhs = 0;
    neighbours(c, [&](size_t nb) {
      ++degree;
      if (!std::isnan(held[nb])) rhs += held[nb];
    });
    inv_diag[c] = Real(1.0 / degree);
    b[c] = Real(rhs);
    x[c] = Real(0.5);
  }
  auto apply = [&](const std::vector<Real>& u, std::vector<Real>& y) {
    parallel_for(cells, [&](size_t c) {
      if (inv_diag[c] == 0) {
        y[c] = 0;
        return;
      }
      double sum = 0;
      int degree = 0;
      neighbours(c, [&](size_t nb) {
        ++degree;
        if (inv_diag[nb] != 0) sum += u[nb];  // held neighbours are in b
      });
      y[c] = Real(degree * double(u[c]) - sum);
    });
  };
  const PcgResult r = pcg_solve(apply, b, inv_diag, 1e-10, 20000, &x);
  iterations_ = r.iterations;
  phi_.assign(cells, std::numeric_limits<double>::quiet_NaN());
  for (size_t c = 0; c < cells; ++c)
    if (inside_[c] && reached[c]) phi_[c] = double(x[c]);
  // Cell gradients: central differences, a missing neighbour (outside the shape) taking the
  // cell's own value, as the no-flux boundary's mirror image has it.
  grad_.assign(cells, Vec3d::Zero());
  parallel_for(cells, [&](size_t c) {
    if (std::isnan(phi_[c])) return;
    const long ci[3] = {long(c % size_t(n_[0])), long(c / size_t(n_[0]) % size_t(n_[1])),
                        long(c / size_t(n_[0]) / size_t(n_[1]))};
    for (int d = 0; d < dim; ++d) {
      double up = phi_[c], down = phi_[c];
      if (ci[d] + 1 < n_[d] && !std::isnan(phi_[size_t(long(c) + stride[d])]))
        up = phi_[size_t(long(c) + stride[d])];
      if (ci[d] > 0 && !std::isnan(phi_[size_t(long(c) - stride[d])]))
        down = phi_[size_t(long(c) - stride[d])];
      grad_[c][d] = (up - down) / (2 * h_);
    }
  });
}

long FlowField::cell_of(const Vec3d& p) const {
  long c = 0, stride = 1;
  for (int d = 0; d < dim_; ++d) {
    const double i = std::floor((p[d] - lo_[d]) / h_);
    if (!(i >= 0 && i < n_[d])) return -1;
    c += long(i) * stride;
    stride *= n_[d];
  }
  return c;
}

double FlowField::potential(const Vec3d& p) const {
  const long c = cell_of(p);
  return c < 0 ? std::numeric_limits<double>::quiet_NaN() : phi_[size_t(c)];
}

Vec3d FlowField::direction(const Vec3d& p, const Vec3d& fallback) const {
  // Multilinear interpolation of the cell gradients between the 2^dim nearest cell centres. A
  // corner without a potential (outside the shape) takes the mirror image of a neighbouring
  // corner's gradient (the components across the flipped axes negated), as the no-flux
  // boundary's ghost cell would: at an axis-aligned wall the normal component is then 0.
  // Near a source or sink the potential is held flat: the flow there is radial.
  for (const Vec3d& q : sources_)
    if ((p - q).norm() <= radius_) return (p - q).norm() > 0 ? Vec3d((p - q).normalized()) : fallback;
  for (const Vec3d& q : sinks_)
    if ((p - q).norm() <= radius_) return (p - q).norm() > 0 ? Vec3d((q - p).normalized()) : fallback;
  const double u[3] = {(p.x() - lo_.x()) / h_ - 0.5, (p.y() - lo_.y()) / h_ - 0.5,
                       dim_ == 3 ? (p.z() - lo_.z()) / h_ - 0.5 : 0.0};
  long base[3];
  double f[3];
  for (int d = 0; d < 3; ++d) base[d] = long(std::floor(u[d])), f[d] = u[d] - double(base[d]);
  const int corners = dim_ == 3 ? 8 : 4;
  auto cell = [&](int corner) -> long {  // -1: off the grid or without a potential
    long c = 0, stride = 1;
    for (int d = 0; d < dim_; ++d) {
      const long i = base[d] + ((corner >> d) & 1);
      if (i < 0 || i >= n_[d]) return -1;
      c += i * stride;
      stride *= n_[d];
    }
    return std::isnan(phi_[size_t(c)]) ? -1 : c;
  };
  long id[8];
  bool any = false;
  for (int k = 0; k < corners; ++k) any = (id[k] = cell(k)) >= 0 || any;
  if (!any) return fallback;
  Vec3d g = Vec3d::Zero();
  for (int k = 0; k < corners; ++k) {
    double w = 1;
    for (int d = 0; d < dim_; ++d) w *= ((k >> d) & 1) ? f[d] : 1 - f[d];
    Vec3d gk = Vec3d::Zero();
    if (id[k] >= 0) {
      gk = grad_[size_t(id[k])];
    } else {
      // The nearest corner that has one: fewest flipped axes first, then in axis order.
      int best = -1;
      for (int flips = 1; flips < corners && best < 0; ++flips)
        for (int m = 1; m < corners && best < 0; ++m)
          if (__builtin_popcount(unsigned(m)) == flips && id[k ^ m] >= 0) best = m;
      gk = grad_[size_t(id[k ^ best])];
      for (int d = 0; d < dim_; ++d)
        if ((best >> d) & 1) gk[d] = -gk[d];
    }
    g += w * gk;
  }
  if (!(g.norm() > 1e-12 / h_)) return fallback;
  return -g.normalized();
}

}  // namespace tear
