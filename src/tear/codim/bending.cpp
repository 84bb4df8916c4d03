#include "tear/codim/bending.h"

#include "tear/exec/parallel.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A segment's rest length and its cross-section's second moment of area.
template <int Dim>
void segment_rest(const Particles<Dim>& el, size_t e, double* length, double* moment) {
  *length = 1 / double(el.rest_inverse[e](0, 0));
  if (Dim == 3) {
    const double r2 = double(el.vol0[e]) / (kPi * *length);
    *moment = kPi * r2 * r2 / 4;
  } else {
    const double w = double(el.vol0[e]) / *length;  // 2 r
    *moment = w * w * w / 12;
  }
}

// A triangle's rest edges in its own frame (the 2x2 inverse of rest_inverse's block).
template <int Dim>
Eigen::Matrix2d triangle_rest(const Particles<Dim>& el, size_t e) {
  Eigen::Matrix2d inv;
  inv << double(el.rest_inverse[e](0, 0)), double(el.rest_inverse[e](0, 1)),
      double(el.rest_inverse[e](1, 0)), double(el.rest_inverse[e](1, 1));
  return inv.inverse();
}

// The cotangent of a rest triangle's angle at corner c.
double rest_cotangent(const Eigen::Matrix2d& Dm, int c) {
  const Eigen::Vector2d p[3] = {Eigen::Vector2d::Zero(), Dm.col(0), Dm.col(1)};
  const Eigen::Vector2d u = p[(c + 1) % 3] - p[c], w = p[(c + 2) % 3] - p[c];
  return u.dot(w) / std::abs(u.x() * w.y() - u.y() * w.x());
}

template <int Dim>
Real plate_rigidity(const MaterialParams& m, const Particles<Dim>& el, size_t e) {
  const double area = std::abs(triangle_rest(el, e).determinant()) / 2;
  const double t = double(el.vol0[e]) / area;
  return Real(double(m.bending_modulus) * t * t * t / (12 * (1 - double(m.nu) * double(m.nu))));
}

// Curves: the tangents, lengths and cosine of hinge h.
template <int Dim>
struct CurveHinge {
  Vec<Dim> t1, t2;
  Real l1, l2, c;
  CurveHinge(const Particles<Dim>& el, size_t h, const Vec<Dim>* x) {
    const uint32_t* v = &el.hinges.corner[el.hinges.begin[h]];
    const Vec<Dim> e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[1]];
    l1 = e1.norm(), l2 = e2.norm();
    t1 = e1 / l1, t2 = e2 / l2;
    c = t1.dot(t2);
  }
};

}  // namespace

template <int Dim>
bool bends(const std::vector<MaterialParams>& materials, const Particles<Dim>& el) {
  if (element_dimension(el.kind) == 0) return false;
  std::vector<bool> seen(materials.size(), false);
  for (size_t e = 0; e < el.size(); ++e) seen[el.material[e]] = true;
  for (size_t m = 0; m < materials.size(); ++m)
    if (seen[m] && materials[m].bending_modulus > 0) return true;
  return false;
}

template <int Dim>
void build_hinges(const std::vector<MaterialParams>& materials, const Particles<Dim>& vertices,
                  Particles<Dim>* el) {
  auto& H = el->hinges;
  if (H.built) return;
  H = {};
  H.begin.push_back(0);
  const size_t nv = vertices.size();
  auto add_hinge = [&](Real stiffness) {
    H.stiffness.push_back(stiffness);
    H.begin.push_back(uint32_t(H.corner.size()));
  };
  const bool on = bends(materials, *el);
  if (on && element_dimension(el->kind) == 1) {
    // Each vertex's segments: a hinge where there are exactly two.
    std::vector<std::array<int64_t, 2>> seg(nv, {-1, -1});
    std::vector<int> count(nv, 0);
    for (size_t e = 0; e < el->size(); ++e)
      for (int k = 0; k < 2; ++k) {
        const uint32_t v = el->element_vertices[e][size_t(k)];
        if (count[v] < 2) seg[v][size_t(count[v])] = int64_t(e);
        ++count[v];
      }
    for (size_t b = 0; b < nv; ++b) {
      if (count[b] != 2) continue;
      const size_t e1 = size_t(seg[b][0]), e2 = size_t(seg[b][1]);
      auto other = [&](size_t e) {
        const auto& ev = el->element_vertices[e];
        return ev[0] == b ? ev[1] : ev[0];
      };
      double L1, I1, L2, I2;
      segment_rest(*el, e1, &L1, &I1);
      segment_rest(*el, e2, &L2, &I2);
      const double B = (double(materials[el->material[e1]].bending_modulus) * I1 +
                        double(materials[el->material[e2]].bending_modulus) * I2) / 2;
      if (!(B > 0)) continue;
      for (uint32_t v : {other(e1), uint32_t(b), other(e2)}) H.corner.push_back(v), H.weight.push_back(0);
      add_hinge(Real(B / ((L1 + L2) / 2)));
    }
  } else if (on) {
    // Each triangle edge (lower vertex, higher vertex, the cotangent opposite it), sorted: an
    // interior edge appears twice, and its weight is half the sum of its two cotangents.
    std::vector<std::tuple<uint32_t, uint32_t, double>> edges;
    edges.reserve(el->size() * 3);
    std::vector<double> area(nv, 0), rigidity(nv, 0);  // mixed (Voronoi) areas, Meyer et al. 2003
    for (size_t e = 0; e < el->size(); ++e) {
      const auto& ev = el->element_vertices[e];
      const Eigen::Matrix2d Dm = triangle_rest(*el, e);
      const Eigen::Vector2d p[3] = {Eigen::Vector2d::Zero(), Dm.col(0), Dm.col(1)};
      const double tri = std::abs(Dm.determinant()) / 2,
                   D = double(plate_rigidity(materials[el->material[e]], *el, e));
      double cot[3];
      for (int k = 0; k < 3; ++k) cot[k] = rest_cotangent(Dm, k);
      const bool obtuse = cot[0] < 0 || cot[1] < 0 || cot[2] < 0;
      for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        const uint32_t a = ev[size_t(k)], b = ev[size_t(k1)];
        edges.emplace_back(std::min(a, b), std::max(a, b), cot[k2]);
        // Corner k's share: its Voronoi region in a non-obtuse triangle, else half the
        // triangle at the obtuse corner and a quarter at the others.
        const double share = !obtuse ? ((p[k1] - p[k]).squaredNorm() * cot[k2] +
                                        (p[k2] - p[k]).squaredNorm() * cot[k1]) / 8
                                     : (cot[k] < 0 ? tri / 2 : tri / 4);
        area[a] += share;
        rigidity[a] += share * D;
      }
    }
    std::sort(edges.begin(), edges.end());
    // Each vertex's ring (neighbour, weight) in neighbour order; a vertex by an edge of other
    // than two triangles is no hinge.
    std::vector<std::vector<std::pair<uint32_t, double>>> ring(nv);
    std::vector<bool> border(nv, false);
    for (size_t i = 0; i < edges.size();) {
      const uint32_t a = std::get<0>(edges[i]), b = std::get<1>(edges[i]);
      size_t j = i;
      double w = 0;
      for (; j < edges.size() && std::get<0>(edges[j]) == a && std::get<1>(edges[j]) == b; ++j)
        w += std::get<2>(edges[j]) / 2;
      if (j - i != 2) border[a] = border[b] = true;
      ring[a].emplace_back(b, w);
      ring[b].emplace_back(a, w);
      i = j;
    }
    for (size_t v = 0; v < nv; ++v) {
      if (border[v] || ring[v].empty() || !(rigidity[v] > 0)) continue;
      std::sort(ring[v].begin(), ring[v].end());
      double sum = 0;
      for (const auto& [u, w] : ring[v]) sum += w;
      H.corner.push_back(uint32_t(v));
      H.weight.push_back(Real(-sum));
      for (const auto& [u, w] : ring[v]) H.corner.push_back(u), H.weight.push_back(Real(w));
      add_hinge(Real(rigidity[v] / (area[v] * area[v])));  // D / A, D = rigidity / A
    }
  }
  // Each vertex's positions in corner[], in hinge order.
  H.vertex_begin.assign(nv + 1, 0);
  for (uint32_t v : H.corner) ++H.vertex_begin[v + 1];
  for (size_t v = 0; v < nv; ++v) H.vertex_begin[v + 1] += H.vertex_begin[v];
  H.incident.resize(H.corner.size());
  std::vector<uint32_t> cursor(H.vertex_begin.begin(), H.vertex_begin.end() - 1);
  for (size_t q = 0; q < H.corner.size(); ++q) H.incident[cursor[H.corner[q]]++] = uint32_t(q);
  H.built = true;
}

namespace {

// A surface hinge's Laplacian row applied to x: sum_c w_c x_c.
template <int Dim>
Vec<Dim> laplacian(const Particles<Dim>& el, size_t h, const Vec<Dim>* x) {
  const auto& H = el.hinges;
  Vec<Dim> sum = Vec<Dim>::Zero();
  for (uint32_t q = H.begin[h]; q < H.begin[h + 1]; ++q) sum += H.weight[q] * x[H.corner[q]];
  return sum;
}

}  // namespace

template <int Dim>
Real hinge_energy(const Particles<Dim>& el, size_t h, const Vec<Dim>* x) {
  const Real s = el.hinges.stiffness[h];
  if (element_dimension(el.kind) == 1) return s * (1 - CurveHinge<Dim>(el, h, x).c);
  return s / 2 * laplacian(el, h, x).squaredNorm();
}

template <int Dim>
void hinge_gradient(const Particles<Dim>& el, size_t h, const Vec<Dim>* x, Vec<Dim>* g) {
  const Real s = el.hinges.stiffness[h];
  if (element_dimension(el.kind) == 1) {
    // E = s (1 - c): dc/de1 = (t2 - c t1) / l1, dc/de2 = (t1 - c t2) / l2; e1 = x_b - x_a,
    // e2 = x_c - x_b.
    const CurveHinge<Dim> k(el, h, x);
    const Vec<Dim> g1 = (k.t2 - k.c * k.t1) / k.l1, g2 = (k.t1 - k.c * k.t2) / k.l2;
    g[0] = s * g1;
    g[1] = s * (g2 - g1);
    g[2] = -s * g2;
    return;
  }
  hinge_hessian_product(el, h, nullptr, x, g);  // quadratic: the gradient is H x
}

template <int Dim>
CurveHingeHessian<Dim> curve_hinge_hessian(const Particles<Dim>& el, size_t h, const Vec<Dim>* x,
                                           bool project) {
  using M = Mat<Dim>;
  const Real s = el.hinges.stiffness[h];
  // In the edge vectors (e1, e2): d2E = -s d2c with
  //   d2c/de1^2 = -(t1 g1^T + g1 t1^T) / l1 - c P1 / l1^2,  d2c/de1 de2 = (P2 / l2 - t1 g2^T) / l1,
  //   d2c/de2^2 = -(t2 g2^T + g2 t2^T) / l2 - c P2 / l2^2,  P = I - t t^T.
  const CurveHinge<Dim> k(el, h, x);
  const Vec<Dim> g1 = (k.t2 - k.c * k.t1) / k.l1, g2 = (k.t1 - k.c * k.t2) / k.l2;
  const M P1 = M::Identity() - k.t1 * k.t1.transpose(), P2 = M::Identity() - k.t2 * k.t2.transpose();
  Eigen::Matrix<Real, 2 * Dim, 2 * Dim> He;
  const M H11 = -(k.t1 * g1.transpose() + g1 * k.t1.transpose()) / k.l1 - k.c * P1 / (k.l1 * k.l1);
  const M H22 = -(k.t2 * g2.transpose() + g2 * k.t2.transpose()) / k.l2 - k.c * P2 / (k.l2 * k.l2);
  const M H12 = (P2 / k.l2 - k.t1 * g2.transpose()) / k.l1;
  He << -s * H11, -s * H12, -s * H12.transpose(), -s * H22;
  He = (He + He.transpose()).eval() / 2;
  if (project) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<Real, 2 * Dim, 2 * Dim>> eig(He);
    He = eig.eigenvectors() * eig.eigenvalues().cwiseMax(Real(0)).asDiagonal() *
         eig.eigenvectors().transpose();
  }
  // x = (x_a, x_b, x_c): e1 = x_b - x_a, e2 = x_c - x_b.
  Eigen::Matrix<Real, 2 * Dim, 3 * Dim> J = Eigen::Matrix<Real, 2 * Dim, 3 * Dim>::Zero();
  J.template block<Dim, Dim>(0, 0) = -M::Identity();
  J.template block<Dim, Dim>(0, Dim) = M::Identity();
  J.template block<Dim, Dim>(Dim, Dim) = -M::Identity();
  J.template block<Dim, Dim>(Dim, 2 * Dim) = M::Identity();
  return J.transpose() * He * J;
}

template <int Dim>
void hinge_hessian_product(const Particles<Dim>& el, size_t h, const CurveHingeHessian<Dim>* curve,
                           const Vec<Dim>* u, Vec<Dim>* y) {
  const auto& H = el.hinges;
  if (element_dimension(el.kind) == 1) {
    Eigen::Matrix<Real, 3 * Dim, 1> us;
    for (int c = 0; c < 3; ++c) us.template segment<Dim>(c * Dim) = u[H.corner[H.begin[h] + uint32_t(c)]];
    const Eigen::Matrix<Real, 3 * Dim, 1> ys = *curve * us;
    for (int c = 0; c < 3; ++c) y[c] = ys.template segment<Dim>(c * Dim);
    return;
  }
  // s w w^T (x) I.
  const uint32_t n = H.corners(h);
  const Real* w = &H.weight[H.begin[h]];
  const Vec<Dim> sum = H.stiffness[h] * laplacian(el, h, u);
  for (uint32_t c = 0; c < n; ++c) y[c] = w[c] * sum;
}

template <int Dim>
Vec<Dim> hinge_hessian_diagonal(const Particles<Dim>& el, size_t h,
                                const CurveHingeHessian<Dim>* curve, uint32_t c) {
  if (element_dimension(el.kind) == 1) return curve->diagonal().template segment<Dim>(int(c) * Dim);
  const Real w = el.hinges.weight[el.hinges.begin[h] + c];
  return Vec<Dim>::Constant(el.hinges.stiffness[h] * w * w);
}

template <int Dim>
void add_bending_forces(const Particles<Dim>& el, Particles<Dim>* vertices) {
  const auto& H = el.hinges;
  std::vector<Vec<Dim>> g(H.corner.size());
  parallel_for(H.size(), [&](size_t h) { hinge_gradient(el, h, vertices->x.data(), &g[H.begin[h]]); });
  parallel_for(vertices->size(), [&](size_t v) {
    Vec<Dim> f = Vec<Dim>::Zero();
    for (uint32_t q = H.vertex_begin[v]; q < H.vertex_begin[v + 1]; ++q) f -= g[H.incident[q]];
    vertices->force[v] += f;
  });
}

template <int Dim>
Real bending_wave_speed(const std::vector<MaterialParams>& materials, const Particles<Dim>& el,
                        double dx) {
  if (!bends(materials, el)) return 0;
  const int gamma = element_dimension(el.kind);
  return parallel_max<Real>(
      el.size(),
      [&](size_t e) {
        const MaterialParams& m = materials[el.material[e]];
        if (!(m.bending_modulus > 0)) return Real(0);
        double ratio, size;  // B / (rho A) and the element's size
        if (gamma == 1) {
          double L, I;
          segment_rest(el, e, &L, &I);
          const double A = double(el.vol0[e]) / L;
          ratio = double(m.bending_modulus) * I / (double(m.rho) * A);
          size = L;
        } else {
          const double area = std::abs(triangle_rest(el, e).determinant()) / 2;
          const double t = double(el.vol0[e]) / area;
          ratio = double(plate_rigidity(m, el, e)) / (double(m.rho) * t);
          size = std::sqrt(2 * area);
        }
        const double h = std::max(size, dx);
        return Real(kPi * kPi * std::sqrt(ratio) / (h * h) * dx / 2);
      },
      Real(0));
}

#define TEAR_BENDING(D)                                                                        \
  template bool bends<D>(const std::vector<MaterialParams>&, const Particles<D>&);            \
  template void build_hinges<D>(const std::vector<MaterialParams>&, const Particles<D>&,      \
                                Particles<D>*);                                                \
  template Real hinge_energy<D>(const Particles<D>&, size_t, const Vec<D>*);                  \
  template void hinge_gradient<D>(const Particles<D>&, size_t, const Vec<D>*, Vec<D>*);       \
  template CurveHingeHessian<D> curve_hinge_hessian<D>(const Particles<D>&, size_t,           \
                                                       const Vec<D>*, bool);                   \
  template void hinge_hessian_product<D>(const Particles<D>&, size_t,                          \
                                         const CurveHingeHessian<D>*, const Vec<D>*, Vec<D>*); \
  template Vec<D> hinge_hessian_diagonal<D>(const Particles<D>&, size_t,                      \
                                            const CurveHingeHessian<D>*, uint32_t);            \
  template void add_bending_forces<D>(const Particles<D>&, Particles<D>*);                    \
  template Real bending_wave_speed<D>(const std::vector<MaterialParams>&, const Particles<D>&, \
                                      double);
TEAR_BENDING(2)
TEAR_BENDING(3)
#undef TEAR_BENDING

}  // namespace tear
