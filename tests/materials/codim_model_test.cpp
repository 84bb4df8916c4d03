// The codimensional models of Jiang et al. 2017 (surface_qr.h, curve_qr.h): stress against the
// energy and dP against the stress by finite differences (in contact, apart and inverted), zero
// stress at rest and under rotation, symmetric Kirchhoff stress, the small-strain moduli, and
// the frictional return maps' properties.
#include <cmath>

#include "material_test_util.h"
#include "tear/materials/registry.h"

namespace tear {
namespace {

using namespace material_test;

MaterialParams codim_material(Model model, Real fs1 = 0, Real fs2 = 0) {
  MaterialParams m = make_material(model, 1000, 0.3, 1, fs1, fs2);
  m.normal_stiffness = 700;  // distinct from E, so that a mixed-up modulus shows
  m.shear_stiffness = 250;
  m.friction = 0.4;
  return m;
}

// F = Q0 R for a random rotation Q0 and an upper triangular R with the given diagonal and
// random off-diagonal entries in [-off, off]: QR gives R back (r11, r22 > 0).
template <int Dim>
Mat<Dim> with_r(std::mt19937_64& rng, const Vec<Dim>& diagonal, double off) {
  std::uniform_real_distribution<double> u(-off, off);
  Mat<Dim> R = diagonal.asDiagonal();
  for (int i = 0; i < Dim; ++i)
    for (int j = i + 1; j < Dim; ++j) R(i, j) = u(rng);
  return random_rotation<Dim>(rng) * R;
}

// Deformations of each kind: the normal (surface: r33; curve: the cross-section) in contact,
// nearly at rest, apart and inverted, with sheared and stretched tangents.
template <int Dim>
std::vector<Mat<Dim>> codim_deformations(std::mt19937_64& rng, int codimension) {
  std::vector<Mat<Dim>> Fs;
  std::uniform_real_distribution<double> stretch(0.6, 1.4);
  for (double normal : {0.3, 0.7, 0.97, 1.3, -0.2}) {
    for (int k = 0; k < 3; ++k) {
      Vec<Dim> d;
      for (int i = 0; i < Dim; ++i) d[i] = stretch(rng);
      if (codimension == 2) {
        d[Dim - 1] = normal;
      } else if (Dim == 2) {
        d[1] = normal;
      } else {
        d[2] = normal / d[1];  // the cross-section's area r22 r33 = normal
      }
      Fs.push_back(with_r<Dim>(rng, d, 0.3));
    }
  }
  return Fs;
}

template <int Dim>
void expect_stress_is_energy_gradient(Model model) {
  std::mt19937_64 rng(11 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  const Mat<Dim> D = Mat<Dim>::Identity();
  for (const Mat<Dim>& F : codim_deformations<Dim>(rng, model_codimension(model))) {
    const Mat<Dim> P = first_piola<Dim>(m, F, D);
    Mat<Dim> fd;
    const double h = 1e-6;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        Mat<Dim> Fp = F, Fm = F;
        Fp(i, j) += h;
        Fm(i, j) -= h;
        fd(i, j) = (energy_density<Dim>(m, Fp, D) - energy_density<Dim>(m, Fm, D)) / (2 * h);
      }
    EXPECT_LT((P - fd).norm(), 1e-6 * (1 + P.norm()))
        << model_name(model) << " Dim " << Dim << "\nF =\n" << F << "\nP =\n" << P
        << "\nfinite difference =\n" << fd;
  }
}

TEST(CodimModels, StressIsTheEnergyGradient) {
  expect_stress_is_energy_gradient<3>(Model::SurfaceQr);
  expect_stress_is_energy_gradient<3>(Model::CurveQr);
  expect_stress_is_energy_gradient<2>(Model::CurveQr);
}

template <int Dim>
void expect_differential_matches_stress_differences(Model model) {
  std::mt19937_64 rng(23 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  const Mat<Dim> D = Mat<Dim>::Identity();
  int checked = 0;
  for (const Mat<Dim>& F : codim_deformations<Dim>(rng, model_codimension(model))) {
    for (int k = 0; k < 3; ++k) {
      const Mat<Dim> dF = random_direction<Dim>(rng);
      const auto stress = [&](const Mat<Dim>& G) { return first_piola<Dim>(m, G, D); };
      const Mat<Dim> dP = stress_differential<Dim>(m, F, D, dF);
      const Mat<Dim> numeric = numeric_stress_differential<Dim>(stress, F, dF);
      EXPECT_LT((numeric - dP).norm(), 1e-6 * (1 + dP.norm()))
          << model_name(model) << " Dim " << Dim << "\nF =\n" << F << "\ndP =\n" << dP
          << "\nnumeric =\n" << numeric;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 45);
}

TEST(CodimModels, StressDifferentialMatchesStressDifferences) {
  expect_differential_matches_stress_differences<3>(Model::SurfaceQr);
  expect_differential_matches_stress_differences<3>(Model::CurveQr);
  expect_differential_matches_stress_differences<2>(Model::CurveQr);
}

// The Hessian (stress_derivative) is symmetric: dP is the second derivative of one energy.
template <int Dim>
void expect_symmetric_hessian(Model model) {
  std::mt19937_64 rng(31 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  for (const Mat<Dim>& F : codim_deformations<Dim>(rng, model_codimension(model))) {
    const StressDerivative<Dim> H = stress_derivative<Dim>(m, F, Mat<Dim>::Identity());
    EXPECT_LT((H - H.transpose()).norm(), 1e-9 * (1 + H.norm())) << model_name(model);
  }
}

TEST(CodimModels, HessianIsSymmetric) {
  expect_symmetric_hessian<3>(Model::SurfaceQr);
  expect_symmetric_hessian<3>(Model::CurveQr);
  expect_symmetric_hessian<2>(Model::CurveQr);
}

// An element moved rigidly (its initial F is a rotation: the rest element lies on the axes)
// has no energy and no stress; nor has one whose normals are only stretched (layers apart).
template <int Dim>
void expect_rigid_motion_is_stress_free(Model model) {
  std::mt19937_64 rng(41 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  const Mat<Dim> D = Mat<Dim>::Identity();
  for (int k = 0; k < 10; ++k) {
    const Mat<Dim> Q = random_rotation<Dim>(rng);
    EXPECT_LT(first_piola<Dim>(m, Q, D).norm(), 1e-12 * m.E) << model_name(model);
    EXPECT_NEAR(energy_density<Dim>(m, Q, D), 0, 1e-12 * m.E);
    Vec<Dim> apart = Vec<Dim>::Ones();
    apart[Dim - 1] = 1.5;  // surface: r33; curve: the cross-section's last axis
    const Mat<Dim> F = Q * apart.asDiagonal();
    EXPECT_LT(first_piola<Dim>(m, F, D).norm(), 1e-12 * m.E) << model_name(model);
    EXPECT_NEAR(energy_density<Dim>(m, F, D), 0, 1e-12 * m.E);
  }
}

TEST(CodimModels, RigidMotionAndSeparatedLayersAreStressFree) {
  expect_rigid_motion_is_stress_free<3>(Model::SurfaceQr);
  expect_rigid_motion_is_stress_free<3>(Model::CurveQr);
  expect_rigid_motion_is_stress_free<2>(Model::CurveQr);
}

// tau = P F^T is symmetric (supplement §2, without angular momentum arguments): the grid
// forces of an element exert no net torque.
template <int Dim>
void expect_symmetric_kirchhoff(Model model) {
  std::mt19937_64 rng(43 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  for (const Mat<Dim>& F : codim_deformations<Dim>(rng, model_codimension(model))) {
    const Mat<Dim> tau = first_piola<Dim>(m, F, Mat<Dim>::Identity()) * F.transpose();
    EXPECT_LT((tau - tau.transpose()).norm(), 1e-10 * (1 + tau.norm())) << model_name(model);
  }
}

TEST(CodimModels, KirchhoffStressIsSymmetric) {
  expect_symmetric_kirchhoff<3>(Model::SurfaceQr);
  expect_symmetric_kirchhoff<3>(Model::CurveQr);
  expect_symmetric_kirchhoff<2>(Model::CurveQr);
}

// Small in-plane strains of a sheet: plane-stress linear elasticity of (E, nu),
// sigma = E / (1 - nu^2) ((1 - nu) eps + nu tr(eps) I) in the plane; with fiber scales, kx and
// ky add to the warp (x) and weft (y) normal stresses.
TEST(CodimModels, SheetInPlaneSmallStrainIsPlaneStress) {
  const double E = 2500, nu = 0.27, eps = 1e-6;
  for (double fs : {0.0, 4.0}) {
    const MaterialParams m = make_material(Model::SurfaceQr, Real(E), Real(nu), 1, Real(fs),
                                           Real(fs / 2));
    std::mt19937_64 rng(7);
    for (int k = 0; k < 5; ++k) {
      Mat<2> H = random_matrix<2>(rng, 1);
      Mat<3> F = Mat<3>::Identity();
      F.topLeftCorner<2, 2>() += eps * H;
      const Mat<2> strain = eps * (H + H.transpose()) / 2;
      Mat<2> sigma = E / (1 - nu * nu) *
                     ((1 - nu) * strain + nu * strain.trace() * Mat<2>::Identity());
      sigma(0, 0) += m.kx * strain(0, 0);
      sigma(1, 1) += m.ky * strain(1, 1);
      const Mat<3> P = first_piola<3>(m, F, Mat<3>::Identity());
      EXPECT_LT((P.topLeftCorner<2, 2>() - sigma).norm(), 1e-4 * sigma.norm()) << "fs " << fs;
      EXPECT_LT(P.col(2).norm() + P.row(2).norm(), 1e-6 * sigma.norm());
    }
  }
}

// A stretched curve: P11 = E (r11 - 1) along the tangent, nothing else.
TEST(CodimModels, CurveStretchIsHookean) {
  for (int dim : {2, 3}) {
    const MaterialParams m = codim_material(Model::CurveQr);
    const Real s = 1.03;
    if (dim == 2) {
      Mat<2> F = Mat<2>::Identity();
      F(0, 0) = s;
      const Mat<2> P = first_piola<2>(m, F, Mat<2>::Identity());
      EXPECT_NEAR(P(0, 0), m.E * (s - 1), 1e-12 * m.E);
      EXPECT_NEAR(P.norm(), std::abs(P(0, 0)), 1e-12 * m.E);
    } else {
      Mat<3> F = Mat<3>::Identity();
      F(0, 0) = s;
      const Mat<3> P = first_piola<3>(m, F, Mat<3>::Identity());
      EXPECT_NEAR(P(0, 0), m.E * (s - 1), 1e-12 * m.E);
      EXPECT_NEAR(P.norm(), std::abs(P(0, 0)), 1e-12 * m.E);
    }
  }
}

// The normal (surface) or the cross-section (curve) compressed: a contact pressure from the
// one-sided energy k/3 (1 - x)^3, the slope -k (1 - x)^2 in the Q basis.
TEST(CodimModels, CompressedNormalPushesBack) {
  const MaterialParams m = codim_material(Model::SurfaceQr);
  Mat<3> F = Mat<3>::Identity();
  F(2, 2) = 0.6;
  const Mat<3> P = first_piola<3>(m, F, Mat<3>::Identity());
  EXPECT_NEAR(P(2, 2), -m.normal_stiffness * 0.4 * 0.4, 1e-12 * m.E);
  const MaterialParams c = codim_material(Model::CurveQr);
  Mat<3> G = Mat<3>::Identity();
  G(1, 1) = 0.5;  // cross-section area 0.5
  const Mat<3> Pc = first_piola<3>(c, G, Mat<3>::Identity());
  // h' cof(Rh) with cof(diag(0.5, 1)) = diag(1, 0.5).
  EXPECT_NEAR(Pc(1, 1), -c.normal_stiffness * 0.25, 1e-12 * c.E);
  EXPECT_NEAR(Pc(2, 2), -c.normal_stiffness * 0.25 * 0.5, 1e-12 * c.E);
}

// ---- return maps ----

// The yield function of a state as its return map sees it (> 0 outside): surface
// gamma |r| - c_F k (1 - r33)^2; curve gamma |Rh r| + c_F p.
template <int Dim>
double yield(const MaterialParams& m, const Mat<Dim>& F) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F, &Q, &R);
  if constexpr (Dim == 3) {
    if (m.model == Model::SurfaceQr) {
      const double r33 = R(2, 2);
      return m.shear_stiffness * std::hypot(R(0, 2), R(1, 2)) -
             m.friction * m.normal_stiffness * (1 - r33) * (1 - r33);
    }
  }
  const double J = Dim == 2 ? R(1, 1) : R(1, 1) * R(2, 2);
  const double p = -J * m.normal_stiffness * (1 - J) * (1 - J);
  const Mat<Dim - 1> Rh = R.template bottomRightCorner<Dim - 1, Dim - 1>();
  const Vec<Dim - 1> r = R.template topRightCorner<1, Dim - 1>().transpose();
  return m.shear_stiffness * (Rh * r).norm() + m.friction * p;
}

template <int Dim>
void expect_return_map_properties(Model model) {
  std::mt19937_64 rng(61 + Dim);
  const MaterialParams m = codim_material(model, 3, 2);
  // At most Dim - 1 (a surface is 3D only): bounds GCC can see (-Warray-bounds).
  const int codimension = std::min(model_codimension(model), Dim - 1);
  int states[4] = {0, 0, 0, 0};
  for (double off : {0.02, 0.3, 1.0}) {
    for (const Mat<Dim>& F0 : codim_deformations<Dim>(rng, codimension)) {
      // Scale the shear so that both sides of the yield surface are visited.
      Mat<Dim> Q, R;
      qr_decompose<Dim>(F0, &Q, &R);
      for (int j = codimension; j < Dim; ++j)
        for (int i = 0; i < j; ++i)
          if (i < codimension) R(i, j) *= off;
      const Mat<Dim> F = Q * R;
      Mat<Dim> G = F;
      const ContactState s = codim_return_map<Dim>(m, &G);
      ++states[int(s)];
      // The tangent columns (the element's own edges) are never changed.
      EXPECT_LT((G.leftCols(codimension) - F.leftCols(codimension)).norm(), 1e-12)
          << model_name(model);
      Mat<Dim> Qg, Rg;
      qr_decompose<Dim>(G, &Qg, &Rg);
      const double y = yield<Dim>(m, F);
      switch (s) {
        case ContactState::Stick:  // inside: unchanged, bit for bit
          EXPECT_LE(y, 0);
          EXPECT_EQ(G, F);
          break;
        case ContactState::Slip:  // on the surface after, pressure unchanged
          EXPECT_GT(y, 0);
          EXPECT_NEAR(yield<Dim>(m, G), 0, 1e-9 * m.E);
          EXPECT_NEAR(Rg(Dim - 1, Dim - 1), R(Dim - 1, Dim - 1), 1e-12);
          break;
        case ContactState::Apart:  // no shear, the normal (cross-section) at rest
        case ContactState::Inverted:
          for (int j = codimension; j < Dim; ++j)
            for (int i = 0; i < codimension; ++i)
              EXPECT_NEAR(Rg(i, j), 0, 1e-12) << model_name(model) << " " << int(s);
          if (s == ContactState::Apart) {
            for (int j = codimension; j < Dim; ++j) {
              EXPECT_NEAR(Rg(j, j), 1, 1e-12);
            }
            if (Dim == 3 && codimension == 1) {
              EXPECT_NEAR(Rg(1, 2), 0, 1e-12);
            }
          }
          break;
      }
      // Idempotent: a state on or inside the surface maps to itself (on it, up to round-off:
      // Q R rounds).
      Mat<Dim> H = G;
      codim_return_map<Dim>(m, &H);
      EXPECT_LT((H - G).norm(), 1e-12) << model_name(model);
    }
  }
  for (int k = 0; k < 4; ++k) EXPECT_GT(states[k], 0) << model_name(model) << " state " << k;
}

TEST(CodimModels, ReturnMapsKeepStatesOnOrInsideTheFrictionLimit) {
  expect_return_map_properties<3>(Model::SurfaceQr);
  expect_return_map_properties<3>(Model::CurveQr);
  expect_return_map_properties<2>(Model::CurveQr);
}

// Coulomb: the shear traction the map allows is c_F times the normal pressure, whatever the
// stiffnesses: in the Q basis tau_13 = gamma r33 |r| and tau_33 = f' r33 (supplement §4.1).
TEST(CodimModels, SheetFrictionLimitIsCoulombsLaw) {
  MaterialParams m = codim_material(Model::SurfaceQr);
  for (double cf : {0.1, 0.5, 1.2}) {
    m.friction = Real(cf);
    Mat<3> F = Mat<3>::Identity();
    F(2, 2) = 0.8;
    F(0, 2) = 5;  // far outside
    codim_return_map<3>(m, &F);
    const Mat<3> tau = first_piola<3>(m, F, Mat<3>::Identity()) * F.transpose();
    EXPECT_NEAR(std::abs(tau(0, 2)), cf * std::abs(tau(2, 2)), 1e-12 * m.E) << cf;
  }
}

TEST(CodimModels, WaveSpeedTakesTheStiffestModulus) {
  MaterialParams m = codim_material(Model::SurfaceQr);
  EXPECT_NEAR(wave_speed(m), std::sqrt(2 * 700.0), 1e-9);  // 2k above E / (1 - nu^2)
  m.normal_stiffness = 10;
  EXPECT_NEAR(wave_speed(m), std::sqrt(1000 / (1 - 0.09)), 1e-9);
  MaterialParams c = codim_material(Model::CurveQr);
  c.normal_stiffness = 10;
  EXPECT_NEAR(wave_speed(c), std::sqrt(1000.0), 1e-9);
}

}  // namespace
}  // namespace tear
