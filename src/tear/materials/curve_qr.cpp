#include "tear/materials/curve_qr.h"

#include "tear/materials/codim_stress.h"

#include <cmath>

namespace tear {

namespace {

// The cross-section Rh, the shear r and the pieces of CurveQr's Q^T P, per dimension.
template <int Dim>
struct Parts;

template <>
struct Parts<2> {
  using Cross = Eigen::Matrix<Real, 1, 1>;
  using Shear = Eigen::Matrix<Real, 1, 1>;
  static Cross cofactor_of(const Cross&) { return Cross::Ones(); }
  static Cross cofactor_differential(const Cross&) { return Cross::Zero(); }
};

template <>
struct Parts<3> {
  using Cross = Mat<2>;
  using Shear = Vec<2>;
  static Cross cofactor_of(const Cross& Rh) { return cofactor<2>(Rh); }
  static Cross cofactor_differential(const Cross& dRh) { return cofactor<2>(dRh); }
};

template <int Dim>
using Cross = typename Parts<Dim>::Cross;
template <int Dim>
using Shear = typename Parts<Dim>::Shear;

template <int Dim>
Real cross_area(const Mat<Dim>& R) {
  return Dim == 2 ? R(1, 1) : R(1, 1) * R(Dim - 1, Dim - 1);
}

template <int Dim>
Mat<Dim> stress_in_q(const MaterialParams& m, const Mat<Dim>& R) {
  constexpr int N = Dim - 1;
  const Cross<Dim> Rh = R.template bottomRightCorner<N, N>();
  const Shear<Dim> r = R.template topRightCorner<1, N>().transpose();
  const codim::OneSided h = codim::one_sided(m.normal_stiffness, cross_area<Dim>(R));
  const Cross<Dim> cof = Parts<Dim>::cofactor_of(Rh);
  const Real gamma = m.shear_stiffness;
  Mat<Dim> G;
  G(0, 0) = m.E * (R(0, 0) - 1);
  G.template topRightCorner<1, N>() = gamma * r.transpose();
  G.template bottomLeftCorner<N, 1>() = (gamma * (Rh * r) - h.f1 * (cof * r)) / R(0, 0);
  G.template bottomRightCorner<N, N>() = h.f1 * cof;
  return G;
}

template <int Dim>
Mat<Dim> stress_in_q_differential(const MaterialParams& m, const Mat<Dim>& R, const Mat<Dim>& dR) {
  constexpr int N = Dim - 1;
  const Cross<Dim> Rh = R.template bottomRightCorner<N, N>();
  const Cross<Dim> dRh = dR.template bottomRightCorner<N, N>();
  const Shear<Dim> r = R.template topRightCorner<1, N>().transpose();
  const Shear<Dim> dr = dR.template topRightCorner<1, N>().transpose();
  const Real J = cross_area<Dim>(R);
  const Cross<Dim> cof = Parts<Dim>::cofactor_of(Rh);
  const Cross<Dim> dcof = Parts<Dim>::cofactor_differential(dRh);
  const Real dJ = cof.cwiseProduct(dRh).sum();  // d det = cof : dRh
  const codim::OneSided h = codim::one_sided(m.normal_stiffness, J);
  const Real gamma = m.shear_stiffness;
  const Real r11 = R(0, 0), dr11 = dR(0, 0);
  const Shear<Dim> b = gamma * (Rh * r) - h.f1 * (cof * r);
  const Shear<Dim> db = gamma * (dRh * r + Rh * dr) - h.f2 * dJ * (cof * r) -
                        h.f1 * (dcof * r + cof * dr);
  Mat<Dim> dG;
  dG(0, 0) = m.E * dr11;
  dG.template topRightCorner<1, N>() = gamma * dr.transpose();
  dG.template bottomLeftCorner<N, 1>() = (db - b * (dr11 / r11)) / r11;
  dG.template bottomRightCorner<N, N>() = h.f2 * dJ * cof + h.f1 * dcof;
  return dG;
}

}  // namespace

void CurveQr::map_parameters(MaterialParams* m, Real, Real) {
  m->normal_stiffness = m->E;
  m->shear_stiffness = m->mu;
  m->friction = kDefaultCodimFriction;
}

template <int Dim>
Real CurveQr::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F, &Q, &R);
  const Real stretch = R(0, 0) - 1;
  return m.E / 2 * stretch * stretch +
         m.shear_stiffness / 2 * R.template topRightCorner<1, Dim - 1>().squaredNorm() +
         codim::one_sided(m.normal_stiffness, cross_area<Dim>(R)).f;
}

template <int Dim>
Mat<Dim> CurveQr::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  return codim::qr_stress<Dim>(F, [&](const Mat<Dim>& R) { return stress_in_q<Dim>(m, R); });
}

template <int Dim>
Mat<Dim> CurveQr::stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                      const Mat<Dim>& dF, Real) {
  return codim::qr_stress_differential<Dim>(
      F, dF, [&](const Mat<Dim>& R) { return stress_in_q<Dim>(m, R); },
      [&](const Mat<Dim>& R, const Mat<Dim>& dR) {
        return stress_in_q_differential<Dim>(m, R, dR);
      });
}

template <int Dim>
ContactState CurveQr::return_map(const MaterialParams& m, Mat<Dim>* F) {
  constexpr int N = Dim - 1;
  Mat<Dim> Q, R;
  qr_decompose<Dim>(*F, &Q, &R);
  const Real J = cross_area<Dim>(R);
  ContactState state;
  if (J >= 1) {
    R.template topRightCorner<1, N>().setZero();
    R.template bottomRightCorner<N, N>().setIdentity();
    state = ContactState::Apart;
  } else if (J <= 0) {
    R.template topRightCorner<1, N>().setZero();
    state = ContactState::Inverted;
  } else {
    // gamma |Rh r| <= -c_F p, p = J h'(J) < 0.
    const Real p = J * codim::one_sided(m.normal_stiffness, J).f1;
    const Cross<Dim> Rh = R.template bottomRightCorner<N, N>();
    const Shear<Dim> r = R.template topRightCorner<1, N>().transpose();
    const Real shear = m.shear_stiffness * (Rh * r).norm();
    const Real limit = -m.friction * p;
    if (shear <= limit) return ContactState::Stick;  // inside: F unchanged, bit for bit
    R.template topRightCorner<1, N>() *= limit / shear;
    state = ContactState::Slip;
  }
  *F = Q * R;
  return state;
}

template Real CurveQr::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real CurveQr::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> CurveQr::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> CurveQr::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> CurveQr::stress_differential<2>(const MaterialParams&, const Mat<2>&,
                                                const Mat<2>&, const Mat<2>&, Real);
template Mat<3> CurveQr::stress_differential<3>(const MaterialParams&, const Mat<3>&,
                                                const Mat<3>&, const Mat<3>&, Real);
template ContactState CurveQr::return_map<2>(const MaterialParams&, Mat<2>*);
template ContactState CurveQr::return_map<3>(const MaterialParams&, Mat<3>*);

}  // namespace tear
