// tests/materials/: random deformations and the finite-difference checks every model's tests
// share (P against the energy, dP against P). Header-only; each test file includes it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "tear/materials/material.h"
#include "tear/math/qr.h"

namespace tear::material_test {

template <int Dim>
Mat<Dim> random_matrix(std::mt19937_64& rng, double range) {
  std::uniform_real_distribution<double> u(-range, range);
  Mat<Dim> A;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) A(i, j) = u(rng);
  return A;
}

template <int Dim>
Mat<Dim> random_rotation(std::mt19937_64& rng) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(random_matrix<Dim>(rng, 1) + 0.1 * Mat<Dim>::Identity(), &Q, &R);
  return Q;
}

// A random direction of unit Frobenius norm.
template <int Dim>
Mat<Dim> random_direction(std::mt19937_64& rng) {
  const Mat<Dim> A = random_matrix<Dim>(rng, 1);
  return A / A.norm();
}

// F = U diag(s) V^T with prescribed singular values (a negative last one inverts F).
template <int Dim>
Mat<Dim> with_singular_values(std::mt19937_64& rng, const Vec<Dim>& s) {
  return random_rotation<Dim>(rng) * s.asDiagonal() * random_rotation<Dim>(rng).transpose();
}

// The deformation gradients every derivative test visits: near identity (|F - I| ~ 0.3), far
// from it (~1), near-singular and inverted.
template <int Dim>
std::vector<Mat<Dim>> test_deformations(std::mt19937_64& rng) {
  std::vector<Mat<Dim>> Fs;
  for (int k = 0; k < 6; ++k) {
    Fs.push_back(Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.3));
    Fs.push_back(Mat<Dim>::Identity() + random_matrix<Dim>(rng, 1.0));
  }
  Vec<Dim> near_singular = Vec<Dim>::Ones(), inverted = Vec<Dim>::Ones();
  near_singular[0] = 1.3;
  near_singular[Dim - 1] = 2e-3;
  inverted[0] = 0.8;
  inverted[Dim - 1] = -0.4;
  for (int k = 0; k < 4; ++k) {
    Fs.push_back(with_singular_values<Dim>(rng, near_singular));
    Fs.push_back(with_singular_values<Dim>(rng, inverted));
  }
  return Fs;
}

constexpr int kTestDeformations = 20;

// An independent reference for dP = dP/dF : dF: central differences of `stress` (F -> P) along
// each entry of F with step h = eps^(1/3) max(1, max |F_ij|), contracted with dF. Truncation
// ~h^2 (third derivative of P) and round-off ~eps P / h: ~1e-10 relative for moderate strains.
template <int Dim, class Stress>
Mat<Dim> numeric_stress_differential(const Stress& stress, const Mat<Dim>& F, const Mat<Dim>& dF) {
  const Real h =
      std::cbrt(std::numeric_limits<Real>::epsilon()) * std::max(Real(1), F.cwiseAbs().maxCoeff());
  Mat<Dim> dP = Mat<Dim>::Zero();
  for (int j = 0; j < Dim; ++j)
    for (int i = 0; i < Dim; ++i) {
      if (dF(i, j) == 0) continue;
      Mat<Dim> Fp = F, Fm = F;
      Fp(i, j) += h;
      Fm(i, j) -= h;
      dP += dF(i, j) * (stress(Fp) - stress(Fm)) / (Fp(i, j) - Fm(i, j));
    }
  return dP;
}

// The material every derivative test uses: E = 1000, nu = 0.3, fiber scales (4, 2).
inline MaterialParams test_material(Model model) {
  return make_material(model, 1000, 0.3, 1, 4, 2);
}

// P = dPsi/dF: central differences of the energy in each entry of F, each F with its own random
// fiber frame D.
template <int Dim>
void expect_stress_is_energy_gradient(Model model, Real g) {
  std::mt19937_64 rng(42 + Dim);
  const MaterialParams m = test_material(model);
  int checked = 0;
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> D = random_rotation<Dim>(rng);
    const Mat<Dim> P = first_piola<Dim>(m, F, D, g);
    const double h = 1e-6;
    Mat<Dim> fd;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        Mat<Dim> Fp = F, Fm = F;
        Fp(i, j) += h;
        Fm(i, j) -= h;
        fd(i, j) = (energy_density<Dim>(m, Fp, D, g) - energy_density<Dim>(m, Fm, D, g)) / (2 * h);
      }
    EXPECT_LT((P - fd).norm(), 1e-6 * (1 + P.norm()))
        << model_name(model) << " Dim " << Dim << " g " << g << "\nF =\n"
        << F << "\nP =\n"
        << P << "\nfinite difference =\n"
        << fd;
    ASSERT_TRUE(P.allFinite());
    ++checked;
  }
  EXPECT_EQ(checked, kTestDeformations);
}

// dP along dF against central differences of P along dF (h = 1e-6), on every test deformation
// with a random fiber frame and direction.
template <int Dim>
void expect_differential_matches_stress_differences(Model model, Real g) {
  std::mt19937_64 rng(7 + Dim);
  const MaterialParams m = test_material(model);
  int checked = 0;
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF, g);
    const double h = 1e-6;
    const Mat<Dim> fd =
        (first_piola<Dim>(m, F + h * dF, D, g) - first_piola<Dim>(m, F - h * dF, D, g)) / (2 * h);
    EXPECT_LT((dP - fd).norm(), 1e-6 * (1 + dP.norm()))
        << model_name(model) << " Dim " << Dim << " g " << g << "\nF =\n"
        << F << "\ndP =\n"
        << dP << "\nfinite difference =\n"
        << fd;
    ASSERT_TRUE(dP.allFinite());
    ++checked;
  }
  EXPECT_EQ(checked, kTestDeformations);
}

// dP(a X + b Y) = a dP(X) + b dP(Y) to round-off, for directions of very different scales.
template <int Dim>
void expect_differential_is_linear(Model model, Real g) {
  std::mt19937_64 rng(3 + Dim);
  const MaterialParams m = test_material(model);
  for (const Mat<Dim>& F : test_deformations<Dim>(rng)) {
    const Mat<Dim> D = random_rotation<Dim>(rng);
    const Mat<Dim> X = random_direction<Dim>(rng), Y = 1e-3 * random_direction<Dim>(rng);
    const Real a = 2.5, b = -40;
    const Mat<Dim> dX = stress_differential<Dim>(m, F, D, X, g);
    const Mat<Dim> dY = stress_differential<Dim>(m, F, D, Y, g);
    const Mat<Dim> combined = stress_differential<Dim>(m, F, D, a * X + b * Y, g);
    const Mat<Dim> expected = a * dX + b * dY;
    EXPECT_LT((combined - expected).norm(),
              1e-12 * (1 + std::abs(a) * dX.norm() + std::abs(b) * dY.norm()))
        << model_name(model) << " Dim " << Dim << " g " << g << "\nF =\n"
        << F;
  }
}

// Central differences of P along dF approach dP as h^2: the error ratio between steps h and h/2
// is ~4. A wrong dP would leave a plateau (ratio ~1). F stays near identity, with det F at
// least 0.05 away from 1 so that the degradation's switch at J = 1 is not crossed.
template <int Dim>
void expect_differential_agrees_at_second_order(Model model, Real g) {
  std::mt19937_64 rng(19 + Dim);
  const MaterialParams m = test_material(model);
  int checked = 0;
  while (checked < 8) {
    const Mat<Dim> F = Mat<Dim>::Identity() + random_matrix<Dim>(rng, 0.3);
    if (std::abs(F.determinant() - 1) < 0.05) continue;
    const Mat<Dim> D = random_rotation<Dim>(rng), dF = random_direction<Dim>(rng);
    const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF, g);
    auto error = [&](double h) {
      const Mat<Dim> fd =
          (first_piola<Dim>(m, F + h * dF, D, g) - first_piola<Dim>(m, F - h * dF, D, g)) / (2 * h);
      return (fd - dP).norm();
    };
    const double e1 = error(4e-3), e2 = error(2e-3), e3 = error(1e-3);
    EXPECT_NEAR(e1 / e2, 4, 0.4) << model_name(model) << " Dim " << Dim << " g " << g;
    EXPECT_NEAR(e2 / e3, 4, 0.4) << model_name(model) << " Dim " << Dim << " g " << g;
    EXPECT_LT(e3, 1e-4 * dP.norm());
    ++checked;
  }
}

}  // namespace tear::material_test
