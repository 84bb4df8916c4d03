// exec/: how loops run. Every parallel loop of tear goes through this header (no TBB outside
// exec/), so an MPI or GPU backend replaces the loops in one place. Deterministic by
// construction: sums over fixed chunks combined in index order, colouring instead of atomics.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

#if defined(__SANITIZE_THREAD__)
#define TEAR_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TEAR_TSAN 1
#endif
#endif

namespace tear {

namespace detail {

// tbb::parallel_for over `range`, body(sub-range) per task. Under ThreadSanitizer the loop's
// fork and join are also made visible: oneTBB hands tasks over and waits for them inside its
// own library, which is not instrumented, so TSan would see a write in a loop body and a read
// after the loop (or a write before it and a read in a task) as a race. Each task acquires
// what the caller released before the loop and releases what the caller acquires after it:
// the ordering TBB gives, told to TSan. Other builds call TBB alone.
template <class Range, class Body>
void tbb_for(const Range& range, const Body& body) {
#ifdef TEAR_TSAN
  std::atomic<unsigned> edge{0};
  edge.store(1, std::memory_order_release);
  tbb::parallel_for(range, [&](const Range& r) {
    (void)edge.load(std::memory_order_acquire);
    body(r);
    edge.fetch_add(1, std::memory_order_acq_rel);
  });
  (void)edge.load(std::memory_order_acquire);
#else
  tbb::parallel_for(range, body);
#endif
}

// fn(i) for i in [first, last) through tbb_for.
template <class Fn>
void for_range(size_t first, size_t last, const Fn& fn) {
  tbb_for(tbb::blocked_range<size_t>(first, last), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) fn(i);
  });
}

}  // namespace detail

// fn(i) for every i in [0, n), in parallel and in no particular order: fn must write only data
// that no other index touches.
template <class Fn>
void parallel_for(size_t n, Fn&& fn) {
  detail::for_range(0, n, fn);
}

// fn(row0, row1, col0, col1) over tiles of at most `tile` x `tile` covering [0, rows) x
// [0, cols) (pictures), in parallel.
template <class Fn>
void parallel_for_tiles(int rows, int cols, int tile, Fn&& fn) {
  detail::tbb_for(tbb::blocked_range2d<int>(0, rows, size_t(tile), 0, cols, size_t(tile)),
                  [&](const tbb::blocked_range2d<int>& r) {
                    fn(r.rows().begin(), r.rows().end(), r.cols().begin(), r.cols().end());
                  });
}

// Scatter without races: `items(g, c)` lists the work items (grid blocks) of group g and colour
// c; items of one colour never write where another item of that colour writes. Colours run one
// after another, within a colour the groups one after another, and the items of one (colour,
// group) in parallel: fn(g, item). As long as each item writes in a fixed order, the result
// does not depend on the thread count.
template <class Items, class Fn>
void for_each_colour(int num_colours, size_t num_groups, Items&& items, Fn&& fn) {
  for (int c = 0; c < num_colours; ++c)
    for (size_t g = 0; g < num_groups; ++g) {
      const std::vector<int>& list = items(g, c);
      detail::for_range(0, list.size(), [&](size_t k) { fn(g, list[k]); });
    }
}

constexpr size_t kReduceChunk = 4096;

// Sum over i in [0, n) of f(i), reduced in a fixed order (chunks of kReduceChunk, partials
// added in index order): bit-identical for any thread count. T needs + and T{} = 0.
template <class T, class Fn>
T deterministic_sum(size_t n, Fn&& f, T zero = T{}) {
  const size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<T> partial(chunks, zero);
  detail::for_range(0, chunks, [&](size_t c) {
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
  detail::for_range(0, chunks, [&](size_t c) {
    T acc = lowest;
    const size_t end = std::min(n, (c + 1) * kReduceChunk);
    for (size_t i = c * kReduceChunk; i < end; ++i) acc = std::max(acc, T(f(i)));
    partial[c] = acc;
  });
  T best = lowest;
  for (const T& p : partial) best = std::max(best, p);
  return best;
}

// Whether f(i) holds for some i in [0, n) (order-independent).
template <class Fn>
bool parallel_any(size_t n, Fn&& f) {
  return parallel_max<char>(
             n, [&](size_t i) { return char(f(i) ? 1 : 0); }, char(0)) != 0;
}

}  // namespace tear
