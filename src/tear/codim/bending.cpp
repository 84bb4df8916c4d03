#include "tear/codim/bending.h"

#include "tear/exec/parallel.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;

template <int Dim>
int hinge_corners(const Particles<Dim>& el) {
  return element_dimension(el.kind) == 1 ? 3 : 4;
}

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
    const auto& v = el.hinges.vertex[h];
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
  const int corners = hinge_corners(*el);
  if (!bends(materials, *el)) {
    H.begin.assign(vertices.size() + 1, 0);
    H.built = true;
    return;
  }
  const int gamma = element_dimension(el->kind);
  const size_t nv = vertices.size();
  if (gamma == 1) {
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
      H.vertex.push_back({other(e1), uint32_t(b), other(e2), 0});
      H.stiffness.push_back(Real(B / ((L1 + L2) / 2)));
      H.weight.push_back({0, 0, 0, 0});
    }
  } else {
    // Each triangle edge (lower vertex, higher vertex, element, opposite corner), sorted: an
    // interior edge appears twice.
    std::vector<std::tuple<uint32_t, uint32_t, uint32_t, int>> edges;
    edges.reserve(el->size() * 3);
    for (size_t e = 0; e < el->size(); ++e)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = el->element_vertices[e][size_t(k)],
                       b = el->element_vertices[e][size_t((k + 1) % 3)];
        edges.emplace_back(std::min(a, b), std::max(a, b), uint32_t(e), (k + 2) % 3);
      }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
      size_t j = i + 1;
      while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
             std::get<1>(edges[j]) == std::get<1>(edges[i]))
        ++j;
      if (j - i == 2) {
        const uint32_t x0 = std::get<0>(edges[i]), x1 = std::get<1>(edges[i]);
        const size_t tri[2] = {std::get<2>(edges[i]), std::get<2>(edges[i + 1])};
        uint32_t opposite[2];
        double cot0[2], cot1[2], area[2], rigidity[2];
        for (int s = 0; s < 2; ++s) {
          const size_t e = tri[s];
          const auto& ev = el->element_vertices[e];
          const int o = std::get<3>(edges[i + size_t(s)]);
          opposite[s] = ev[size_t(o)];
          int c0 = 0, c1 = 0;
          for (int c = 0; c < 3; ++c) {
            if (ev[size_t(c)] == x0) c0 = c;
            if (ev[size_t(c)] == x1) c1 = c;
          }
          const Eigen::Matrix2d Dm = triangle_rest(*el, e);
          cot0[s] = rest_cotangent(Dm, c0);
          cot1[s] = rest_cotangent(Dm, c1);
          area[s] = std::abs(Dm.determinant()) / 2;
          rigidity[s] = double(plate_rigidity(materials[el->material[e]], *el, e));
        }
        const double D = (rigidity[0] + rigidity[1]) / 2;
        if (D > 0) {
          H.vertex.push_back({x0, x1, opposite[0], opposite[1]});
          H.stiffness.push_back(Real(D / (area[0] + area[1])));
          H.weight.push_back({Real(cot1[0] + cot1[1]), Real(cot0[0] + cot0[1]),
                              Real(-(cot0[0] + cot1[0])), Real(-(cot0[1] + cot1[1]))});
        }
      }
      i = j;
    }
  }
  // Each vertex's (hinge, slot) pairs, in hinge order.
  H.begin.assign(nv + 1, 0);
  for (const auto& v : H.vertex)
    for (int s = 0; s < corners; ++s) ++H.begin[v[size_t(s)] + 1];
  for (size_t v = 0; v < nv; ++v) H.begin[v + 1] += H.begin[v];
  H.incident.resize(H.begin[nv]);
  std::vector<uint32_t> cursor(H.begin.begin(), H.begin.end() - 1);
  for (size_t h = 0; h < H.vertex.size(); ++h)
    for (int s = 0; s < corners; ++s) H.incident[cursor[H.vertex[h][size_t(s)]]++] = uint32_t(h * 4 + size_t(s));
  H.built = true;
}

template <int Dim>
Real hinge_energy(const Particles<Dim>& el, size_t h, const Vec<Dim>* x) {
  const Real s = el.hinges.stiffness[h];
  if (element_dimension(el.kind) == 1) return s * (1 - CurveHinge<Dim>(el, h, x).c);
  const auto& v = el.hinges.vertex[h];
  const auto& K = el.hinges.weight[h];
  const Vec<Dim> sum = K[0] * x[v[0]] + K[1] * x[v[1]] + K[2] * x[v[2]] + K[3] * x[v[3]];
  return s / 2 * sum.squaredNorm();
}

template <int Dim>
void hinge_gradient(const Particles<Dim>& el, size_t h, const Vec<Dim>* x,
                    std::array<Vec<Dim>, 4>* g) {
  const Real s = el.hinges.stiffness[h];
  if (element_dimension(el.kind) == 1) {
    // E = s (1 - c): dc/de1 = (t2 - c t1) / l1, dc/de2 = (t1 - c t2) / l2; e1 = x_b - x_a,
    // e2 = x_c - x_b.
    const CurveHinge<Dim> k(el, h, x);
    const Vec<Dim> g1 = (k.t2 - k.c * k.t1) / k.l1, g2 = (k.t1 - k.c * k.t2) / k.l2;
    (*g)[0] = s * g1;
    (*g)[1] = s * (g2 - g1);
    (*g)[2] = -s * g2;
    (*g)[3].setZero();
    return;
  }
  const auto& v = el.hinges.vertex[h];
  const auto& K = el.hinges.weight[h];
  const Vec<Dim> sum = K[0] * x[v[0]] + K[1] * x[v[1]] + K[2] * x[v[2]] + K[3] * x[v[3]];
  for (int j = 0; j < 4; ++j) (*g)[size_t(j)] = (s * K[size_t(j)]) * sum;
}

template <int Dim>
HingeHessian<Dim> hinge_hessian(const Particles<Dim>& el, size_t h, const Vec<Dim>* x,
                                bool project) {
  using M = Mat<Dim>;
  const Real s = el.hinges.stiffness[h];
  HingeHessian<Dim> out = HingeHessian<Dim>::Zero();
  if (element_dimension(el.kind) == 2) {
    // s K K^T (x) I: constant, positive semi-definite.
    const auto& K = el.hinges.weight[h];
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        out.template block<Dim, Dim>(a * Dim, b * Dim) = (s * K[size_t(a)] * K[size_t(b)]) * M::Identity();
    return out;
  }
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
  Eigen::Matrix<Real, 2 * Dim, 4 * Dim> J = Eigen::Matrix<Real, 2 * Dim, 4 * Dim>::Zero();
  J.template block<Dim, Dim>(0, 0) = -M::Identity();
  J.template block<Dim, Dim>(0, Dim) = M::Identity();
  J.template block<Dim, Dim>(Dim, Dim) = -M::Identity();
  J.template block<Dim, Dim>(Dim, 2 * Dim) = M::Identity();
  out = J.transpose() * He * J;
  return out;
}

template <int Dim>
void add_bending_forces(const Particles<Dim>& el, Particles<Dim>* vertices) {
  const auto& H = el.hinges;
  std::vector<std::array<Vec<Dim>, 4>> g(H.size());
  parallel_for(H.size(), [&](size_t h) { hinge_gradient(el, h, vertices->x.data(), &g[h]); });
  parallel_for(vertices->size(), [&](size_t v) {
    Vec<Dim> f = Vec<Dim>::Zero();
    for (uint32_t q = H.begin[v]; q < H.begin[v + 1]; ++q) f -= g[H.incident[q] / 4][H.incident[q] % 4];
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
  template void hinge_gradient<D>(const Particles<D>&, size_t, const Vec<D>*,                 \
                                  std::array<Vec<D>, 4>*);                                     \
  template HingeHessian<D> hinge_hessian<D>(const Particles<D>&, size_t, const Vec<D>*, bool); \
  template void add_bending_forces<D>(const Particles<D>&, Particles<D>*);                    \
  template Real bending_wave_speed<D>(const std::vector<MaterialParams>&, const Particles<D>&, \
                                      double);
TEAR_BENDING(2)
TEAR_BENDING(3)
#undef TEAR_BENDING

}  // namespace tear
