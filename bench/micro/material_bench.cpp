// Google Benchmark micro benches: cost of one first Piola-Kirchhoff stress evaluation and of one
// stress differential dP (per registered model), of the polar rotation (fast vs the SVD
// reference) and of the per-particle damage driving force.
// `tear bench` reports the stress comparison as JSON; this is the profiler-friendly variant.
#include "tear/damage/driving_force.h"
#include "tear/materials/material.h"
#include "tear/materials/registry.h"
#include "tear/math/polar.h"
#include "tear/math/qr.h"
#include "tear/math/svd.h"

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

namespace tear {
namespace {

// F = I + A, entries of A uniform in [-0.4, 0.4] (strains up to ~50%, some stress states of
// every sign pattern); random orthonormal fiber frames D.
template <int Dim>
struct Pool {
  std::vector<Mat<Dim>> F, D;
  explicit Pool(size_t n) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-0.4, 0.4);
    for (size_t i = 0; i < n; ++i) {
      Mat<Dim> A, B, Q, R;
      for (int r = 0; r < Dim; ++r)
        for (int c = 0; c < Dim; ++c) A(r, c) = u(rng), B(r, c) = u(rng);
      F.push_back(Mat<Dim>::Identity() + A);
      qr_decompose<Dim>(Mat<Dim>::Identity() + B, &Q, &R);
      D.push_back(Q);
    }
  }
};

// The same frames, with F a random rotation times I + A, A in [-0.05, 0.05]: the milder
// strains of most particles in a simulation, arbitrarily rotated.
template <int Dim>
struct MildPool : Pool<Dim> {
  explicit MildPool(size_t n) : Pool<Dim>(n) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-1, 1);
    for (Mat<Dim>& F : this->F) {
      Mat<Dim> B, Q, R;
      for (int k = 0; k < Dim * Dim; ++k) B.data()[k] = u(rng);
      qr_decompose<Dim>(B, &Q, &R);
      F = Q * (Mat<Dim>::Identity() + (F - Mat<Dim>::Identity()) / 8);
    }
  }
};

template <int Dim>
const Pool<Dim>& pool_by_index(int64_t index) {
  static const Pool<Dim> wide(4096);
  static const MildPool<Dim> mild(4096);
  return index == 0 ? wide : mild;
}

const char* pool_name(int64_t index) { return index == 0 ? "wide" : "mild"; }

template <int Dim>
void BM_FirstPiola(benchmark::State& state) {
  const Pool<Dim>& pool = pool_by_index<Dim>(0);
  const MaterialParams m = make_material(Model(state.range(0)), 1e4, 0.3, 1, 2, 1);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(first_piola<Dim>(m, pool.F[i], pool.D[i]));
    i = (i + 1) & 4095;
  }
  state.SetLabel(model_name(m.model));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_FirstPiola, 2)->DenseRange(0, Models::kCount - 1);
BENCHMARK_TEMPLATE(BM_FirstPiola, 3)->DenseRange(0, Models::kCount - 1);

// dP along a fixed direction (every model's differential is analytic).
template <int Dim>
void BM_StressDifferential(benchmark::State& state) {
  const Pool<Dim>& pool = pool_by_index<Dim>(0);
  const MaterialParams m = make_material(Model(state.range(0)), 1e4, 0.3, 1, 2, 1);
  const Mat<Dim> dF = Mat<Dim>::Constant(Real(0.1)) + Mat<Dim>::Identity();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(stress_differential<Dim>(m, pool.F[i], pool.D[i], dF));
    i = (i + 1) & 4095;
  }
  state.SetLabel(model_name(m.model));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_StressDifferential, 2)->DenseRange(0, Models::kCount - 1);
BENCHMARK_TEMPLATE(BM_StressDifferential, 3)->DenseRange(0, Models::kCount - 1);

// The projected (PSD) stress derivative a Newton step uses per particle: Dim^2 differentials and
// a symmetric eigen-decomposition of the Dim^2 x Dim^2 matrix.
template <int Dim>
void BM_ProjectedStressDerivative(benchmark::State& state) {
  const Pool<Dim>& pool = pool_by_index<Dim>(0);
  const MaterialParams m = make_material(Model(state.range(0)), 1e4, 0.3, 1, 2, 1);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(projected_stress_derivative<Dim>(m, pool.F[i], pool.D[i]));
    i = (i + 1) & 4095;
  }
  state.SetLabel(model_name(m.model));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_ProjectedStressDerivative, 2)->DenseRange(0, Models::kCount - 1);
BENCHMARK_TEMPLATE(BM_ProjectedStressDerivative, 3)->DenseRange(0, Models::kCount - 1);

// Polar rotation of F = R S: first argument 0 the signed-SVD reference, 1 polar_rotation();
// second argument the pool (0 wide, 1 mild).
template <int Dim>
void BM_PolarRotation(benchmark::State& state) {
  const Pool<Dim>& pool = pool_by_index<Dim>(state.range(1));
  const bool fast = state.range(0) == 1;
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fast ? polar_rotation<Dim>(pool.F[i])
                                  : polar_rotation_svd<Dim>(pool.F[i]));
    i = (i + 1) & 4095;
  }
  state.SetLabel(std::string(fast ? "fast " : "svd ") + pool_name(state.range(1)));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_PolarRotation, 2)->ArgsProduct({{0, 1}, {0, 1}});
BENCHMARK_TEMPLATE(BM_PolarRotation, 3)->ArgsProduct({{0, 1}, {0, 1}});

// Damage driving force Phi of one qr_aniso particle (undegraded Cauchy stress, tensile part,
// structural tensor with both fibers active), as update_driving_force() calls it; argument
// the pool (0 wide, 1 mild).
template <int Dim>
void BM_ParticlePhi(benchmark::State& state) {
  const Pool<Dim>& pool = pool_by_index<Dim>(state.range(0));
  const MaterialParams m = make_material(Model::QrAniso, 1e4, 0.3, 1, 2, 1);
  const Real alpha[2] = {-1, -0.5};
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(particle_phi<Dim>(m, pool.F[i], pool.D[i], alpha, 100));
    i = (i + 1) & 4095;
  }
  state.SetLabel(pool_name(state.range(0)));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_ParticlePhi, 2)->DenseRange(0, 1);
BENCHMARK_TEMPLATE(BM_ParticlePhi, 3)->DenseRange(0, 1);

}  // namespace
}  // namespace tear

BENCHMARK_MAIN();
