// Google Benchmark micro benches: cost of one first Piola-Kirchhoff stress evaluation.
// `tear bench` reports the same comparison as JSON; this is the profiler-friendly variant.
#include "tear/materials/material.h"
#include "tear/math/qr.h"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace tear {
namespace {

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

template <int Dim>
void BM_FirstPiola(benchmark::State& state) {
  static const Pool<Dim> pool(4096);
  const MaterialParams m = make_material(Model(state.range(0)), 1e4, 0.3, 1, 2, 1);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(first_piola<Dim>(m, pool.F[i], pool.D[i]));
    i = (i + 1) & 4095;
  }
  state.SetLabel(model_name(m.model));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_TEMPLATE(BM_FirstPiola, 2)->DenseRange(0, 3);
BENCHMARK_TEMPLATE(BM_FirstPiola, 3)->DenseRange(0, 3);

}  // namespace
}  // namespace tear

BENCHMARK_MAIN();
