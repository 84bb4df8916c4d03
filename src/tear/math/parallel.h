// math/: deterministic parallel reductions. Sums are taken over fixed-size chunks and the
// chunk partials combined in index order, so results are bit-identical for any thread count.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace tear {

constexpr size_t kReduceChunk = 4096;

// Returns sum over i in [0, n) of f(i), reduced in a fixed order. T needs + and T{} = 0.
template <class T, class Fn>
T deterministic_sum(size_t n, Fn&& f, T zero = T{}) {
  const size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<T> partial(chunks, zero);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    T acc = zero;
    const size_t end = std::min(n, (c + 1) * kReduceChunk);
    for (size_t i = c * kReduceChunk; i < end; ++i) acc += f(i);
    partial[c] = acc;
  });
  T total = zero;
  for (const T& p : partial) total += p;
  return total;
}

// Max over [0, n) of f(i); max is order-independent, so any schedule gives the same bits.
template <class T, class Fn>
T parallel_max(size_t n, Fn&& f, T lowest) {
  const size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<T> partial(chunks, lowest);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    T acc = lowest;
    const size_t end = std::min(n, (c + 1) * kReduceChunk);
    for (size_t i = c * kReduceChunk; i < end; ++i) acc = std::max(acc, T(f(i)));
    partial[c] = acc;
  });
  T best = lowest;
  for (const T& p : partial) best = std::max(best, p);
  return best;
}

}  // namespace tear
