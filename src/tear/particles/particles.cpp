#include "tear/particles/particles.h"

namespace tear {

template <int Dim>
void Particles<Dim>::resize(size_t n) {
  x.resize(n), v.resize(n), C.resize(n), F.resize(n), fiber.resize(n);
  mass.resize(n), vol0.resize(n), damage.resize(n), drive.resize(n), id.resize(n);
  material.resize(n);
}

template <int Dim>
void Particles<Dim>::push_back(const Vec<Dim>& pos, const Vec<Dim>& vel, const Mat<Dim>& frame,
                               Real m, Real v0, uint16_t mat) {
  id.push_back(uint32_t(x.size()));
  x.push_back(pos), v.push_back(vel);
  C.push_back(Mat<Dim>::Zero()), F.push_back(Mat<Dim>::Identity()), fiber.push_back(frame);
  mass.push_back(m), vol0.push_back(v0), damage.push_back(0), drive.push_back(0);
  material.push_back(mat);
}

namespace {
template <class T>
void apply_order(std::vector<T>& a, const std::vector<uint32_t>& order) {
  std::vector<T> out(a.size());
  for (size_t k = 0; k < order.size(); ++k) out[k] = a[order[k]];
  a.swap(out);
}
}  // namespace

template <int Dim>
void Particles<Dim>::permute(const std::vector<uint32_t>& order) {
  TEAR_ASSERT(order.size() == size());
  apply_order(x, order), apply_order(v, order), apply_order(C, order), apply_order(F, order);
  apply_order(fiber, order), apply_order(mass, order), apply_order(vol0, order);
  apply_order(damage, order), apply_order(drive, order), apply_order(id, order);
  apply_order(material, order);
}

template struct Particles<2>;
template struct Particles<3>;

}  // namespace tear
