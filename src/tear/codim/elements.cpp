#include "tear/codim/elements.h"

#include "tear/codim/bending.h"

#include "tear/exec/parallel.h"

#include <Eigen/Geometry>
#include <cmath>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A unit vector normal to unit t (3D).
Vec3d any_normal(const Vec3d& t) {
  const int k = std::abs(t.x()) <= std::abs(t.y()) && std::abs(t.x()) <= std::abs(t.z()) ? 0
                : std::abs(t.y()) <= std::abs(t.z())                               ? 1
                                                                                   : 2;
  return t.cross(Vec3d::Unit(k)).normalized();
}

template <int Dim>
Vec<Dim> head(const Vec3d& v) {
  return v.head<Dim>().template cast<Real>();
}

}  // namespace

template <int Dim>
void append_codim_body(const CodimMesh& mesh, const CodimBody& body, Particles<Dim>* vertices,
                       Particles<Dim>* elements) {
  using M = Mat<Dim>;
  const int gamma = mesh.manifold;
  const size_t first = vertices->size();
  const size_t corners = mesh.corners();
  auto velocity_at = [&](const Vec3d& x) -> Vec3d {  // a value, not an Eigen expression
    return body.velocity + body.angular_velocity.cross(x - body.center);
  };
  // Element volumes first: the vertices' lumped masses need all of them.
  std::vector<double> volume(mesh.elements.size());
  std::vector<double> vertex_mass(mesh.vertices.size(), 0.0);
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& el = mesh.elements[e];
    const Vec3d d1 = mesh.vertices[el[1]] - mesh.vertices[el[0]];
    if (gamma == 1) {
      volume[e] = d1.norm() * (Dim == 2 ? 2 * body.radius : kPi * body.radius * body.radius);
    } else {
      const Vec3d d2 = mesh.vertices[el[2]] - mesh.vertices[el[0]];
      volume[e] = d1.cross(d2).norm() / 2 * body.thickness;
    }
    for (size_t c = 0; c < corners; ++c) vertex_mass[el[c]] += body.rho * volume[e] / double(corners);
  }
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    vertices->push_back(head<Dim>(mesh.vertices[v]), head<Dim>(velocity_at(mesh.vertices[v])),
                        M::Identity(), Real(vertex_mass[v]), 0, body.material);
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& el = mesh.elements[e];
    Vec3d centroid = Vec3d::Zero();
    for (size_t c = 0; c < corners; ++c) centroid += mesh.vertices[el[c]] / double(corners);
    Vec3d v = Vec3d::Zero();
    for (size_t c = 0; c < corners; ++c) v += velocity_at(mesh.vertices[el[c]]) / double(corners);
    const size_t i = elements->size();
    elements->push_back(head<Dim>(centroid), head<Dim>(v), M::Identity(), 0, Real(volume[e]),
                        body.material);
    elements->element_vertices[i] = {uint32_t(first + el[0]), uint32_t(first + el[1]),
                                     uint32_t(corners == 3 ? first + el[2] : first + el[1])};
    // The rest frame [t1 (t2) n...] and D^-1; F at rest is that frame.
    const Vec3d d1 = mesh.vertices[el[1]] - mesh.vertices[el[0]];
    M frame = M::Identity(), inverse = M::Identity();
    if (gamma == 1) {
      const Vec3d t = d1.normalized();
      inverse(0, 0) = Real(1 / d1.norm());
      if constexpr (Dim == 2) {
        frame << Real(t.x()), Real(-t.y()), Real(t.y()), Real(t.x());
      } else {
        const Vec3d n2 = any_normal(t);
        frame.col(0) = t.cast<Real>();
        frame.col(1) = n2.cast<Real>();
        frame.col(2) = t.cross(n2).cast<Real>();
      }
    } else if constexpr (Dim == 3) {
      const Vec3d d2 = mesh.vertices[el[2]] - mesh.vertices[el[0]];
      const Vec3d n = d1.cross(d2).normalized();
      Vec3d t1 = body.warp - body.warp.dot(n) * n;
      if (!(t1.norm() > 1e-6 * body.warp.norm())) t1 = d1;  // no warp, or along the normal
      t1.normalize();
      const Vec3d t2 = n.cross(t1);
      Eigen::Matrix2d Dm;
      Dm << t1.dot(d1), t1.dot(d2), t2.dot(d1), t2.dot(d2);
      inverse.template topLeftCorner<2, 2>() = Dm.inverse().cast<Real>();
      frame.col(0) = t1.cast<Real>();
      frame.col(1) = t2.cast<Real>();
      frame.col(2) = n.cast<Real>();
    }
    elements->F[i] = frame;
    elements->rest_inverse[i] = inverse;
  }
}

template <int Dim>
void codim_vertex_forces(const std::vector<MaterialParams>& materials,
                         std::vector<Particles<Dim>>* groups) {
  for (Particles<Dim>& el : *groups) {
    const int gamma = element_dimension(el.kind);
    if (gamma == 0) continue;
    Particles<Dim>& vx = (*groups)[size_t(el.vertex_group)];
    // The elements' stresses and their corners' shares of the normal stress, in parallel.
    const Real share = Real(1) / Real(gamma + 1);
    parallel_for(el.size(), [&](size_t e) {
      const MaterialParams& m = materials[el.material[e]];
      el.stress[e] = el.vol0[e] * first_piola<Dim>(m, el.F[e], Mat<Dim>::Identity());
      el.normal_stress[e] = share * element_normal_stress(el, e);
    });
    // Each vertex sums over its elements in element order (a fixed order: the same bits for
    // any thread count), in parallel over vertices through the incidence list.
    const size_t corners = size_t(gamma + 1);
    if (vx.incident_begin.size() != vx.size() + 1 || vx.incident.size() != el.size() * corners) {
      vx.incident_begin.assign(vx.size() + 1, 0);
      for (size_t e = 0; e < el.size(); ++e)
        for (size_t k = 0; k < corners; ++k) ++vx.incident_begin[el.element_vertices[e][k] + 1];
      for (size_t v = 0; v < vx.size(); ++v) vx.incident_begin[v + 1] += vx.incident_begin[v];
      vx.incident.resize(el.size() * corners);
      std::vector<uint32_t> cursor(vx.incident_begin.begin(), vx.incident_begin.end() - 1);
      for (size_t e = 0; e < el.size(); ++e)
        for (size_t k = 0; k < corners; ++k)
          vx.incident[cursor[el.element_vertices[e][k]]++] = uint32_t(e * corners + k);
    }
    parallel_for(vx.size(), [&](size_t v) {
      Vec<Dim> force = Vec<Dim>::Zero();
      Mat<Dim> stress = Mat<Dim>::Zero();
      for (uint32_t k = vx.incident_begin[v]; k < vx.incident_begin[v + 1]; ++k) {
        const size_t e = vx.incident[k] / corners, corner = vx.incident[k] % corners;
        const Mat<Dim>& VP = el.stress[e];
        const Mat<Dim>& Dinv = el.rest_inverse[e];
        // Column b of -VP_t Dm^-T, -sum_eps VP(:, eps) Dinv(b, eps) (eps over the tangents),
        // on tangent corner b + 1; corner 0 takes minus their sum.
        auto tangent_force = [&](int b) {
          Vec<Dim> f = -VP.col(0) * Dinv(b, 0);
          for (int eps = 1; eps < gamma; ++eps) f -= VP.col(eps) * Dinv(b, eps);
          return f;
        };
        if (corner == 0) {
          Vec<Dim> sum = tangent_force(0);
          for (int b = 1; b < gamma; ++b) sum += tangent_force(b);
          force -= sum;
        } else {
          force += tangent_force(int(corner) - 1);
        }
        stress += el.normal_stress[e];
      }
      vx.force[v] = force;
      vx.stress[v] = stress;
    });
    build_hinges(materials, vx, &el);
    if (el.hinges.size() > 0) add_bending_forces(el, &vx);
  }
}

template <int Dim>
Mat<Dim> element_normal_stress(const Particles<Dim>& elements, size_t e) {
  const int gamma = element_dimension(elements.kind);
  const Mat<Dim>& VP = elements.stress[e];
  const Mat<Dim>& F = elements.F[e];
  Mat<Dim> tau = VP.col(gamma) * F.col(gamma).transpose();
  for (int c = gamma + 1; c < Dim; ++c) tau += VP.col(c) * F.col(c).transpose();
  return tau;
}

template <int Dim>
void update_element_geometry(const Particles<Dim>& vertices, Real dt, Particles<Dim>* elements) {
  const int gamma = element_dimension(elements->kind);
  const Real share = Real(1) / Real(gamma + 1);
  parallel_for(elements->size(), [&](size_t e) {
    const std::array<uint32_t, 3>& c = elements->element_vertices[e];
    Vec<Dim> x = vertices.x[c[0]], v = vertices.v[c[0]];
    Mat<Dim> C = vertices.C[c[0]];
    for (int k = 1; k <= gamma; ++k) {
      x += vertices.x[c[size_t(k)]];
      v += vertices.v[c[size_t(k)]];
      C += vertices.C[c[size_t(k)]];
    }
    elements->x[e] = x * share;
    elements->v[e] = v * share;
    elements->C[e] = C * share;
    Mat<Dim>& F = elements->F[e];
    // The normals: d_n <- (I + dt C) d_n, C the element's velocity gradient (its vertices').
    const Mat<Dim> G = Mat<Dim>::Identity() + dt * elements->C[e];
    for (int col = gamma; col < Dim; ++col) F.col(col) = G * F.col(col);
    // The tangents: F_t = [x1 - x0 (x2 - x0)] Dm^-1.
    const Mat<Dim>& Dinv = elements->rest_inverse[e];
    Eigen::Matrix<Real, Dim, 2> edges = Eigen::Matrix<Real, Dim, 2>::Zero();
    for (int k = 0; k < gamma; ++k) edges.col(k) = vertices.x[c[size_t(k) + 1]] - vertices.x[c[0]];
    for (int col = 0; col < gamma; ++col) {
      Vec<Dim> f = edges.col(0) * Dinv(0, col);
      for (int k = 1; k < gamma; ++k) f += edges.col(k) * Dinv(k, col);
      F.col(col) = f;
    }
  });
}

template void append_codim_body<2>(const CodimMesh&, const CodimBody&, Particles<2>*,
                                   Particles<2>*);
template void append_codim_body<3>(const CodimMesh&, const CodimBody&, Particles<3>*,
                                   Particles<3>*);
template void codim_vertex_forces<2>(const std::vector<MaterialParams>&,
                                     std::vector<Particles<2>>*);
template void codim_vertex_forces<3>(const std::vector<MaterialParams>&,
                                     std::vector<Particles<3>>*);
template Mat<2> element_normal_stress<2>(const Particles<2>&, size_t);
template Mat<3> element_normal_stress<3>(const Particles<3>&, size_t);
template void update_element_geometry<2>(const Particles<2>&, Real, Particles<2>*);
template void update_element_geometry<3>(const Particles<3>&, Real, Particles<3>*);

}  // namespace tear
