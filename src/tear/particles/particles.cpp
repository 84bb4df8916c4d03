#include "tear/particles/particles.h"

#include <cstring>

namespace tear {

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

template struct Particles<2>;
template struct Particles<3>;

}  // namespace tear
