#include "tear/particles/particles.h"

#include "tear/math/qr.h"

#include <cstring>

namespace tear {

template <int Dim>
Particles<Dim>::Particles(GroupKind group_kind) : kind(group_kind) {
  if (kind == GroupKind::Volumetric) {
    enable("fiber");
  } else if (kind == GroupKind::MeshVertices) {
    enable("force");
    enable("stress");  // its elements' normal stress shares, for P2G
  } else {
    enable("element_vertices");
    enable("rest_inverse");
    enable("contact");
    enable("stress");  // the element's V P, for its vertices' forces and P2G
    enable("normal_stretch");
    enable("normal_stress");
  }
}

template <int Dim>
std::vector<std::string> Particles<Dim>::requestable_columns() const {
  std::vector<std::string> out;
  for (const std::string& name : optional_columns())
    if (name != "contact" && name != "normal_stretch") out.push_back(name);
  return out;
}

template <int Dim>
bool Particles<Dim>::is_identity(const M& frame) {
  return std::memcmp(&frame, &kIdentity, sizeof(M)) == 0;
}

template <int Dim>
void Particles<Dim>::push_back(const V& pos, const V& vel, const M& frame, Real m, Real v0,
                               uint16_t mat) {
  const size_t i = append();
  id[i] = uint32_t(i);
  x[i] = pos;
  v[i] = vel;
  if (!is_identity(frame)) enable("fiber");
  if (!fiber.empty()) fiber[i] = frame;
  mass[i] = m;
  vol0[i] = v0;
  material[i] = mat;
}

template <int Dim>
void Particles<Dim>::world_fiber_of(const FieldRegistry& store, size_t i, double* out) {
  const auto& p = static_cast<const Particles<Dim>&>(store);
  const M& D = p.fiber_of(i);
  const V f = p.F[i] * D.col(0);
  const Real len = f.norm();
  const V a = len > 0 ? V(f / len) : V(D.col(0));
  for (int d = 0; d < 3; ++d) out[d] = d < Dim ? double(a[d]) : 0.0;
}

template <int Dim>
bool Particles<Dim>::drop_identity_fibers() {
  if (!enabled("fiber")) return true;
  if (parallel_any(fiber.size(), [&](size_t i) { return !is_identity(fiber[i]); })) return false;
  disable("fiber");
  return true;
}

template <int Dim>
void Particles<Dim>::driving_force_of(const FieldRegistry& store, size_t i, double* out) {
  const auto& p = static_cast<const Particles<Dim>&>(store);
  out[0] = p.drive.size() > i ? double(p.drive[i]) : 0.0;
}

template <int Dim>
void Particles<Dim>::normal_stretch_of(const FieldRegistry& store, size_t i, double* out) {
  const auto& p = static_cast<const Particles<Dim>&>(store);
  M Q, R;
  qr_decompose<Dim>(p.F[i], &Q, &R);
  out[0] = p.kind == GroupKind::SurfaceElements ? double(R(Dim - 1, Dim - 1))
           : Dim == 2                           ? double(R(1, 1))
                                                : double(R(1, 1) * R(Dim - 1, Dim - 1));
}

template struct Particles<2>;
template struct Particles<3>;

}  // namespace tear
