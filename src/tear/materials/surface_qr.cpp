#include "tear/materials/surface_qr.h"

#include "tear/materials/codim_stress.h"
#include "tear/materials/fixed_corotated.h"

#include <cmath>

namespace tear {

namespace {

using M2 = Mat<2>;
using V2 = Vec<2>;

// |(a, b)| without hypot's care for overflow (a tenth of a step's time in libm's hypot):
// entries of R are stretches, far from the limits.
inline Real norm2(Real a, Real b) { return std::sqrt(a * a + b * b); }

// The in-plane energy h and its gradient dh/dRh (Rh upper triangular, r11 >= 0, r22 >= 0).
// The fixed corotated part is rotation invariant and the fiber terms' (dh/dRh) Rh^T is
// symmetric, so dh/dRh is the block's Q^T P as it is (no mirrored triangle enters).
Real in_plane_energy(const MaterialParams& m, const M2& Rh) {
  const Real n2 = norm2(Rh(0, 1), Rh(1, 1));
  return FixedCorotated::energy<2>(m, Rh, M2::Identity(), 1) +
         m.kx / 2 * (Rh(0, 0) - 1) * (Rh(0, 0) - 1) + m.ky / 2 * (n2 - 1) * (n2 - 1);
}

M2 in_plane_stress(const MaterialParams& m, const M2& Rh) {
  M2 P = FixedCorotated::first_piola<2>(m, Rh, M2::Identity(), 1);
  P(0, 0) += m.kx * (Rh(0, 0) - 1);
  const Real n2 = norm2(Rh(0, 1), Rh(1, 1));
  if (m.ky != 0 && n2 > 0) {
    const Real b = m.ky * (n2 - 1) / n2;
    P(0, 1) += b * Rh(0, 1);
    P(1, 1) += b * Rh(1, 1);
  }
  return P;
}

M2 in_plane_stress_differential(const MaterialParams& m, const M2& Rh, const M2& dRh) {
  M2 dP = FixedCorotated::stress_differential<2>(m, Rh, M2::Identity(), dRh, 1);
  dP(0, 0) += m.kx * dRh(0, 0);
  const Real n2 = norm2(Rh(0, 1), Rh(1, 1));
  if (m.ky != 0 && n2 > 0) {
    // d/dc of ky (n2 - 1) c / n2 for c = (r12, r22): ky [(1 - 1/n2) dc + (c . dc) c / n2^3].
    const V2 c(Rh(0, 1), Rh(1, 1)), dc(dRh(0, 1), dRh(1, 1));
    const V2 d = m.ky * ((1 - 1 / n2) * dc + c.dot(dc) / (n2 * n2 * n2) * c);
    dP(0, 1) += d[0];
    dP(1, 1) += d[1];
  }
  return dP;
}

// Q^T P as a function of R (surface_qr.h).
Mat<3> stress_in_q(const MaterialParams& m, const Mat<3>& R) {
  const M2 Rh = R.topLeftCorner<2, 2>();
  const V2 r = R.topRightCorner<2, 1>();
  const Real r33 = R(2, 2);
  const codim::OneSided f = codim::one_sided(m.normal_stiffness, r33);
  const Real gamma = m.shear_stiffness;
  Mat<3> G;
  G.topLeftCorner<2, 2>() = in_plane_stress(m, Rh);
  G.topRightCorner<2, 1>() = gamma * r;
  // (Rh^-1 r): Rh upper triangular.
  const V2 s(0, r[1] / Rh(1, 1));
  const V2 a((r[0] - Rh(0, 1) * s[1]) / Rh(0, 0), s[1]);
  G.bottomLeftCorner<1, 2>() = (gamma * r33 - f.f1) * a.transpose();
  G(2, 2) = f.f1;
  return G;
}

Mat<3> stress_in_q_differential(const MaterialParams& m, const Mat<3>& R, const Mat<3>& dR) {
  const M2 Rh = R.topLeftCorner<2, 2>(), dRh = dR.topLeftCorner<2, 2>();
  const V2 r = R.topRightCorner<2, 1>(), dr = dR.topRightCorner<2, 1>();
  const Real r33 = R(2, 2), dr33 = dR(2, 2);
  const codim::OneSided f = codim::one_sided(m.normal_stiffness, r33);
  const Real gamma = m.shear_stiffness;
  const M2 inv = Rh.inverse();
  const V2 a = inv * r;
  const V2 da = inv * (dr - dRh * a);
  Mat<3> dG;
  dG.topLeftCorner<2, 2>() = in_plane_stress_differential(m, Rh, dRh);
  dG.topRightCorner<2, 1>() = gamma * dr;
  dG.bottomLeftCorner<1, 2>() =
      ((gamma - f.f2) * dr33 * a + (gamma * r33 - f.f1) * da).transpose();
  dG(2, 2) = f.f2 * dr33;
  return dG;
}

}  // namespace

void SurfaceQr::map_parameters(MaterialParams* m, Real fiber_scale1, Real fiber_scale2) {
  m->lambda = m->E * m->nu / (1 - m->nu * m->nu);
  m->kx = fiber_scale1 * m->mu;
  m->ky = fiber_scale2 * m->mu;
  m->normal_stiffness = m->E;
  m->shear_stiffness = m->mu;
  m->friction = kDefaultCodimFriction;
}

template <int Dim>
Real SurfaceQr::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  if constexpr (Dim != 3) {
    TEAR_ASSERT(!"surface_qr is a 3D model");
    return 0;
  } else {
    Mat<3> Q, R;
    qr_decompose<3>(F, &Q, &R);
    const V2 r = R.topRightCorner<2, 1>();
    return in_plane_energy(m, R.topLeftCorner<2, 2>()) + m.shear_stiffness / 2 * r.squaredNorm() +
           codim::one_sided(m.normal_stiffness, R(2, 2)).f;
  }
}

template <int Dim>
Mat<Dim> SurfaceQr::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                Real) {
  if constexpr (Dim != 3) {
    TEAR_ASSERT(!"surface_qr is a 3D model");
    return Mat<Dim>::Zero();
  } else {
    return codim::qr_stress<3>(F, [&](const Mat<3>& R) { return stress_in_q(m, R); });
  }
}

template <int Dim>
Mat<Dim> SurfaceQr::stress_differential(const MaterialParams& m, const Mat<Dim>& F,
                                        const Mat<Dim>&, const Mat<Dim>& dF, Real) {
  if constexpr (Dim != 3) {
    TEAR_ASSERT(!"surface_qr is a 3D model");
    return Mat<Dim>::Zero();
  } else {
    return codim::qr_stress_differential<3>(
        F, dF, [&](const Mat<3>& R) { return stress_in_q(m, R); },
        [&](const Mat<3>& R, const Mat<3>& dR) { return stress_in_q_differential(m, R, dR); });
  }
}

template <int Dim>
ContactState SurfaceQr::return_map(const MaterialParams& m, Mat<Dim>* F) {
  if constexpr (Dim != 3) {
    TEAR_ASSERT(!"surface_qr is a 3D model");
    return ContactState::Apart;
  } else {
    Mat<3> Q, R;
    qr_decompose<3>(*F, &Q, &R);
    const Real r33 = R(2, 2);
    const Real shear = norm2(R(0, 2), R(1, 2));
    ContactState state = ContactState::Stick;
    if (r33 >= 1) {
      R(0, 2) = R(1, 2) = 0;
      R(2, 2) = 1;
      state = ContactState::Apart;
    } else if (r33 < 0) {
      R(0, 2) = R(1, 2) = 0;
      state = ContactState::Inverted;
    } else {
      // gamma |r| <= c_F k (1 - r33)^2.
      const Real limit =
          m.friction * m.normal_stiffness * (1 - r33) * (1 - r33) / m.shear_stiffness;
      if (shear <= limit) return ContactState::Stick;  // inside: F unchanged, bit for bit
      const Real s = limit / shear;
      R(0, 2) *= s;
      R(1, 2) *= s;
      state = ContactState::Slip;
    }
    *F = Q * R;
    return state;
  }
}

template Real SurfaceQr::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real SurfaceQr::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> SurfaceQr::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                          Real);
template Mat<3> SurfaceQr::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                          Real);
template Mat<2> SurfaceQr::stress_differential<2>(const MaterialParams&, const Mat<2>&,
                                                  const Mat<2>&, const Mat<2>&, Real);
template Mat<3> SurfaceQr::stress_differential<3>(const MaterialParams&, const Mat<3>&,
                                                  const Mat<3>&, const Mat<3>&, Real);
template ContactState SurfaceQr::return_map<2>(const MaterialParams&, Mat<2>*);
template ContactState SurfaceQr::return_map<3>(const MaterialParams&, Mat<3>*);

}  // namespace tear
