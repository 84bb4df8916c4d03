#include "tear/materials/material.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "tear/materials/registry.h"

namespace tear {

Real lame_mu(Real E, Real nu) { return E / (2 * (1 + nu)); }
Real lame_lambda(Real E, Real nu) { return E * nu / ((1 + nu) * (1 - 2 * nu)); }

MaterialParams make_material(Model model, Real E, Real nu, Real rho, Real fiber_scale1,
                             Real fiber_scale2) {
  MaterialParams m;
  m.model = model;
  m.E = E;
  m.nu = nu;
  m.rho = rho;
  m.mu = lame_mu(E, nu);
  m.lambda = lame_lambda(E, nu);
  visit_model(model, [&](auto M) { M.map_parameters(&m, fiber_scale1, fiber_scale2); });
  return m;
}

Real wave_speed(const MaterialParams& m) {
  const int codimension = model_codimension(m.model);
  if (codimension == 0) {
    const Real modulus = lame_lambda(m.E, m.nu) + 2 * lame_mu(m.E, m.nu) + std::max(m.kx, m.ky);
    return std::sqrt(modulus / m.rho);
  }
  const Real along = (codimension == 2 ? m.E / (1 - m.nu * m.nu) : m.E) + std::max(m.kx, m.ky);
  const Real modulus = std::max({along, m.shear_stiffness, 2 * m.normal_stiffness});
  return std::sqrt(modulus / m.rho);
}

int model_codimension(Model m) {
  const int i = int(m);
  return i >= 0 && i < Models::kCount ? kModelTraits[i].codimension : 0;
}

template <int Dim>
ContactState codim_return_map(const MaterialParams& m, Mat<Dim>* F) {
  return visit_model(m.model, [&](auto M) {
    if constexpr (decltype(M)::kCodimension > 0) {
      return M.template return_map<Dim>(m, F);
    } else {
      TEAR_ASSERT(!"codim_return_map of a volumetric model");
      return ContactState::Apart;
    }
  });
}

template ContactState codim_return_map<2>(const MaterialParams&, Mat<2>*);
template ContactState codim_return_map<3>(const MaterialParams&, Mat<3>*);

const char* model_name(Model m) {
  const int i = int(m);
  return i >= 0 && i < Models::kCount ? kModelTraits[i].name : "?";
}

bool parse_model(const std::string& name, Model* out) {
  for (const ModelTraits& t : kModelTraits) {
    if (name == t.name) {
      *out = t.model;
      return true;
    }
  }
  return false;
}

template <int Dim>
Real energy_density(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  return visit_model(m.model, [&](auto M) { return M.energy(m, F, D, g); });
}

template <int Dim>
Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  return visit_model(m.model, [&](auto M) { return M.first_piola(m, F, D, g); });
}

template <int Dim>
Mat<Dim> kirchhoff_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  return visit_model(m.model, [&](auto M) -> Mat<Dim> {
    if constexpr (decltype(M)::kClosedFormKirchhoff) return M.kirchhoff_stress(m, F, D, g);
    else return M.first_piola(m, F, D, g) * F.transpose();
  });
}

template <int Dim>
Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                             const Mat<Dim>& dF, Real g) {
  return visit_model(m.model, [&](auto M) { return M.stress_differential(m, F, D, dF, g); });
}

template <int Dim>
StressDerivative<Dim> stress_derivative(const MaterialParams& m, const Mat<Dim>& F,
                                        const Mat<Dim>& D, Real g) {
  StressDerivative<Dim> A;
  visit_model(m.model, [&](auto M) {
    for (int k = 0; k < Dim * Dim; ++k) {
      Mat<Dim> dF = Mat<Dim>::Zero();
      dF(k % Dim, k / Dim) = 1;  // column-major: entry (i, j) is k = i + Dim j
      A.col(k) = M.stress_differential(m, F, D, dF, g).reshaped();
    }
  });
  return A;
}

template <int Dim>
StressDerivative<Dim> projected_stress_derivative(const MaterialParams& m, const Mat<Dim>& F,
                                                  const Mat<Dim>& D, Real g) {
  const StressDerivative<Dim> A = stress_derivative<Dim>(m, F, D, g);
  const StressDerivative<Dim> sym = (A + A.transpose()) / 2;
  // Positive definite already (most particles near rest): its own projection. The Cholesky
  // test costs a fraction of the eigen-decomposition.
  if (Eigen::LLT<StressDerivative<Dim>>(sym).info() == Eigen::Success) return sym;
  Eigen::SelfAdjointEigenSolver<StressDerivative<Dim>> eig(sym);
  const auto values = eig.eigenvalues().cwiseMax(Real(0));
  return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
}

template Real energy_density<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real energy_density<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> kirchhoff_stress<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> kirchhoff_stress<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> stress_differential<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                       const Mat<2>&, Real);
template Mat<3> stress_differential<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                       const Mat<3>&, Real);
template StressDerivative<2> stress_derivative<2>(const MaterialParams&, const Mat<2>&,
                                                  const Mat<2>&, Real);
template StressDerivative<3> stress_derivative<3>(const MaterialParams&, const Mat<3>&,
                                                  const Mat<3>&, Real);
template StressDerivative<2> projected_stress_derivative<2>(const MaterialParams&, const Mat<2>&,
                                                           const Mat<2>&, Real);
template StressDerivative<3> projected_stress_derivative<3>(const MaterialParams&, const Mat<3>&,
                                                           const Mat<3>&, Real);

}  // namespace tear
