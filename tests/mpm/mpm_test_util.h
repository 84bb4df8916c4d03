// Helpers for MPM tests: scenes and particle blocks built in code (no files).
#pragma once

#include "tear/mpm/solver.h"

namespace tear::testing {

inline Scene basic_scene(int dim, double dx, Vec3d lo, Vec3d hi, Model model, double E,
                         double nu, double rho, double fiber_scale = 0) {
  Scene s;
  s.name = "test";
  s.dim = dim;
  s.dx = dx;
  s.domain_min = lo;
  s.domain_max = hi;
  s.walls = ContactType::None;
  s.cfl = 0.4;
  s.max_dt = 1e-2;
  MaterialSpec m;
  m.name = "m";
  m.params = make_material(model, Real(E), Real(nu), Real(rho), Real(fiber_scale), 0);
  m.fiber_scale[0] = Real(fiber_scale);
  s.materials.push_back(m);
  return s;
}

// A regular lattice of k^Dim particles per cell filling [lo, hi] (cell-aligned), fibers
// along x, velocity v(x).
template <int Dim, class VelFn>
Particles<Dim> lattice_block(const Scene& s, const Vec<Dim>& lo, const Vec<Dim>& hi, int k,
                             VelFn vel) {
  Particles<Dim> p;
  const Real h = Real(s.dx) / k;
  IVec<Dim> n;
  for (int d = 0; d < Dim; ++d) n[d] = int(std::lround((hi[d] - lo[d]) / h));
  const Real vol = std::pow(h, Real(Dim));
  const Real rho = s.materials[0].params.rho;
  IVec<Dim> i = IVec<Dim>::Zero();
  while (true) {
    const Vec<Dim> x = lo + (i.template cast<Real>() + Vec<Dim>::Constant(Real(0.5))) * h;
    p.push_back(x, vel(x), Mat<Dim>::Identity(), rho * vol, vol, 0);
    int d = 0;
    while (d < Dim && ++i[d] == n[d]) i[d++] = 0;
    if (d == Dim) break;
  }
  return p;
}

}  // namespace tear::testing
