// Return maps (materials/plasticity.h): the stress they measure is StVK-Hencky's; after a
// projection the state is on the yield surface, inside it nothing changes; von Mises keeps the
// volume and the principal directions and hardens monotonically; Drucker-Prager's apex, its
// cohesion and its volume correction.
#include "tear/materials/plasticity.h"

#include "material_test_util.h"
#include "tear/materials/material.h"
#include "tear/math/svd.h"

#include <cmath>

namespace tear {
namespace {

using namespace material_test;

constexpr Real kE = 1000, kNu = 0.3;

// The Kirchhoff stress of the stvk_hencky model itself (P F^T), against which the yield
// functions are written.
template <int Dim>
Mat<Dim> hencky_kirchhoff(const Mat<Dim>& F) {
  const MaterialParams m = make_material(Model::StvkHencky, kE, kNu, 1);
  return first_piola<Dim>(m, F, Mat<Dim>::Identity()) * F.transpose();
}

template <int Dim>
Mat<Dim> dev(const Mat<Dim>& tau) {
  return tau - tau.trace() / Dim * Mat<Dim>::Identity();
}

// Random deformations with det F > 0, from small to large strains.
template <int Dim>
std::vector<Mat<Dim>> deformations(std::mt19937_64& rng) {
  std::vector<Mat<Dim>> Fs;
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  for (int k = 0; k < 40; ++k) {
    Vec<Dim> s;
    for (int i = 0; i < Dim; ++i) s[i] = std::exp(u(rng) * (1 + k % 3));
    Fs.push_back(with_singular_values<Dim>(rng, s));
  }
  return Fs;
}

template <int Dim>
void expect_von_mises_surface_is_hencky_stress() {
  std::mt19937_64 rng(1);
  const PlasticParams p = von_mises(kE, kNu, 30, 0);
  for (const Mat<Dim>& F : deformations<Dim>(rng)) {
    const Real eq = std::sqrt(Real(1.5)) * dev<Dim>(hencky_kirchhoff<Dim>(F)).norm();
    EXPECT_NEAR(yield_function<Dim>(p, F, {}), eq - 30, 1e-9 * kE);
  }
}

TEST(Plasticity, VonMisesMeasuresTheStvkHenckyKirchhoffStress) {
  expect_von_mises_surface_is_hencky_stress<2>();
  expect_von_mises_surface_is_hencky_stress<3>();
}

template <int Dim>
void expect_drucker_prager_surface_is_hencky_stress() {
  std::mt19937_64 rng(2);
  const Real phi = 30, c = 5;
  const PlasticParams p = drucker_prager(kE, kNu, phi, c);
  const Real s = std::sin(phi * Real(M_PI / 180)), fit = std::sqrt(Real(2) / 3) / (3 - s);
  for (const Mat<Dim>& F : deformations<Dim>(rng)) {
    const Mat<Dim> tau = hencky_kirchhoff<Dim>(F);
    const Real f = dev<Dim>(tau).norm() + fit * 2 * s * tau.trace() -
                   fit * 6 * c * std::cos(phi * Real(M_PI / 180));
    EXPECT_NEAR(yield_function<Dim>(p, F, {}), f, 1e-9 * kE);
  }
}

TEST(Plasticity, DruckerPragerMeasuresTheStvkHenckyKirchhoffStress) {
  expect_drucker_prager_surface_is_hencky_stress<2>();
  expect_drucker_prager_surface_is_hencky_stress<3>();
}

// Outside: projected onto the surface, with the same volume and principal directions (von
// Mises flow is deviatoric and coaxial); inside: F and the state untouched, bit for bit.
template <int Dim>
void expect_von_mises_projects_onto_its_surface(Real hardening) {
  std::mt19937_64 rng(3);
  const PlasticParams p = von_mises(kE, kNu, 250, hardening);
  int projected = 0, inside = 0;
  for (const Mat<Dim>& F0 : deformations<Dim>(rng)) {
    Mat<Dim> F = F0;
    PlasticState s{0.05, 0};
    const bool was_outside = yield_function<Dim>(p, F0, s) > 0;
    EXPECT_EQ(return_map<Dim>(p, &F, &s), was_outside);
    if (!was_outside) {
      ++inside;
      EXPECT_EQ(F, F0);
      EXPECT_EQ(s.strain, Real(0.05));
      continue;
    }
    ++projected;
    EXPECT_NEAR(yield_function<Dim>(p, F, s), 0, 1e-9 * kE);
    EXPECT_NEAR(F.determinant(), F0.determinant(), 1e-12 * F0.determinant());
    EXPECT_GT(s.strain, Real(0.05));
    // Coaxial: F0^-1 F is symmetric positive definite along the same right singular vectors,
    // i.e. F = F0 S with S symmetric.
    const Mat<Dim> S = F0.inverse() * F;
    EXPECT_LT((S - S.transpose()).norm(), 1e-10);
  }
  EXPECT_GT(projected, 5);
  EXPECT_GT(inside, 5);
}

TEST(Plasticity, VonMisesProjectsOntoItsSurfaceAndLeavesTheInsideAlone) {
  expect_von_mises_projects_onto_its_surface<2>(0);
  expect_von_mises_projects_onto_its_surface<3>(0);
  expect_von_mises_projects_onto_its_surface<2>(500);
  expect_von_mises_projects_onto_its_surface<3>(500);
}

// Keep shearing: with hardening the stress at the surface grows with the plastic strain (and
// the plastic strain with the shear); without it, it stays at the yield stress.
template <int Dim>
void expect_hardening_is_monotone() {
  for (Real H : {Real(0), Real(200), Real(2000)}) {
    const PlasticParams p = von_mises(kE, kNu, 20, H);
    Mat<Dim> F = Mat<Dim>::Identity();
    PlasticState s;
    Real last_stress = 0, last_strain = 0;
    for (int k = 0; k < 30; ++k) {
      Mat<Dim> shear = Mat<Dim>::Identity();
      shear(0, 1) = Real(0.02);
      F = shear * F;
      return_map<Dim>(p, &F, &s);
      const Real eq = std::sqrt(Real(1.5)) * dev<Dim>(hencky_kirchhoff<Dim>(F)).norm();
      EXPECT_LE(eq, 20 + H * s.strain + 1e-9 * kE);
      if (k > 5) {  // yielding by now
        EXPECT_NEAR(eq, 20 + H * s.strain, 1e-9 * kE) << H;
        EXPECT_GT(s.strain, last_strain);
        if (H > 0)
          EXPECT_GT(eq, last_stress) << H;
        else
          EXPECT_NEAR(eq, last_stress, 1e-9 * kE);
      }
      last_stress = eq;
      last_strain = s.strain;
    }
  }
}

TEST(Plasticity, VonMisesHardeningIsMonotone) {
  expect_hardening_is_monotone<2>();
  expect_hardening_is_monotone<3>();
}

// One radial return is exact: projecting in one step or in many small steps along the same
// straining path at a fixed strain direction gives the same state (the stress is linear in the
// Hencky strain, and the return is along the deviator).
TEST(Plasticity, VonMisesOneStepEqualsManySmallStepsOnARadialPath) {
  const PlasticParams p = von_mises(kE, kNu, 10, 300);
  const Vec<3> dir(0.7, -0.2, -0.5);  // deviatoric
  Mat<3> F_one = (0.2 * dir).array().exp().matrix().asDiagonal();
  PlasticState one;
  return_map<3>(p, &F_one, &one);
  Mat<3> F_many = Mat<3>::Identity();
  PlasticState many;
  for (int k = 0; k < 50; ++k) {
    F_many = Mat<3>((0.2 / 50 * dir).array().exp().matrix().asDiagonal()) * F_many;
    return_map<3>(p, &F_many, &many);
  }
  EXPECT_NEAR((F_one - F_many).norm(), 0, 1e-12);
  EXPECT_NEAR(one.strain, many.strain, 1e-12);
}

template <int Dim>
void expect_drucker_prager_projection() {
  std::mt19937_64 rng(4);
  const PlasticParams p = drucker_prager(kE, kNu, 35, 0, false);
  int side = 0, apex = 0, inside = 0;
  for (const Mat<Dim>& F0 : deformations<Dim>(rng)) {
    Mat<Dim> F = F0;
    PlasticState s;
    const bool was_outside = yield_function<Dim>(p, F0, s) > 0;
    EXPECT_EQ(return_map<Dim>(p, &F, &s), was_outside);
    if (!was_outside) {
      ++inside;
      EXPECT_EQ(F, F0);
      continue;
    }
    EXPECT_NEAR(yield_function<Dim>(p, F, s), 0, 1e-9 * kE);
    if (F0.determinant() >= 1) {
      // Expansion: to the apex, a stress-free rotation (no cohesion).
      ++apex;
      EXPECT_NEAR((F.transpose() * F - Mat<Dim>::Identity()).norm(), 0, 1e-12);
      EXPECT_NEAR(hencky_kirchhoff<Dim>(F).norm(), 0, 1e-9 * kE);
    } else {
      // Compression: sheared back at the same volume.
      ++side;
      EXPECT_NEAR(F.determinant(), F0.determinant(), 1e-12);
    }
  }
  EXPECT_GT(side, 3);
  EXPECT_GT(apex, 3);
  EXPECT_GT(inside, 3);
}

TEST(Plasticity, DruckerPragerProjectsOntoTheConeOrItsApex) {
  expect_drucker_prager_projection<2>();
  expect_drucker_prager_projection<3>();
}

// Cohesion moves the apex into tension: a small isotropic stretch is then elastic, and a
// large one ends at the apex, where tr(tau) = cohesion_term / friction.
TEST(Plasticity, DruckerPragerCohesionCarriesTension) {
  const PlasticParams p = drucker_prager(kE, kNu, 30, 10, false);
  const Real bulk = 3 * p.lambda + 2 * p.mu, apex_trace = p.cohesion_term / p.friction;
  const Real small = std::exp(apex_trace / bulk / 3 / 2);  // half way to the apex
  Mat<3> F = small * Mat<3>::Identity();
  PlasticState s;
  EXPECT_FALSE(return_map<3>(p, &F, &s));
  F = Real(1.2) * Mat<3>::Identity();
  EXPECT_TRUE(return_map<3>(p, &F, &s));
  EXPECT_NEAR(hencky_kirchhoff<3>(F).trace(), apex_trace, 1e-9 * kE);
  EXPECT_NEAR(dev<3>(hencky_kirchhoff<3>(F)).norm(), 0, 1e-9 * kE);
  // Without cohesion the same stretch is stress-free.
  const PlasticParams dry = drucker_prager(kE, kNu, 30, 0, false);
  F = small * Mat<3>::Identity();
  EXPECT_TRUE(return_map<3>(dry, &F, &s));
  EXPECT_NEAR((F - Mat<3>::Identity()).norm(), 0, 1e-12);
}

// Expanded by 10 % per side, then compressed by 5 %: with the volume correction the grain
// still owes volume, so it stays stress-free at the apex; without it the compression builds
// pressure at once.
TEST(Plasticity, DruckerPragerVolumeCorrectionSpendsTheVolumeGainedAtTheApex) {
  for (bool correct : {true, false}) {
    const PlasticParams p = drucker_prager(kE, kNu, 30, 0, correct);
    Mat<2> F = Real(1.1) * Mat<2>::Identity();
    PlasticState s;
    EXPECT_TRUE(return_map<2>(p, &F, &s));
    EXPECT_NEAR((F - Mat<2>::Identity()).norm(), 0, 1e-12);
    EXPECT_NEAR(s.volume, correct ? 2 * std::log(1.1) : 0, 1e-12);
    F = Real(0.95) * F;
    return_map<2>(p, &F, &s);
    if (correct) {
      EXPECT_NEAR((F - Mat<2>::Identity()).norm(), 0, 1e-12);
      EXPECT_NEAR(s.volume, 2 * std::log(1.1 * 0.95), 1e-12);
    } else {
      EXPECT_NEAR((F - Real(0.95) * Mat<2>::Identity()).norm(), 0, 1e-12);
      EXPECT_LT(hencky_kirchhoff<2>(F).trace(), -10);
    }
    // Compressed past the debt: the rest of the compression is elastic, the debt spent.
    F = Real(0.9) * F;
    return_map<2>(p, &F, &s);
    EXPECT_EQ(s.volume, 0);
    const Real expected = correct ? Real(0.9 * 0.95 * 1.1) : Real(0.9 * 0.95);
    EXPECT_NEAR((F - expected * Mat<2>::Identity()).norm(), 0, 1e-12) << correct;
  }
}

TEST(Plasticity, NoneLeavesFAlone) {
  Mat<3> F = 2 * Mat<3>::Identity();
  PlasticState s;
  EXPECT_FALSE(return_map<3>(PlasticParams{}, &F, &s));
  EXPECT_EQ(F, 2 * Mat<3>::Identity());
}

}  // namespace
}  // namespace tear
