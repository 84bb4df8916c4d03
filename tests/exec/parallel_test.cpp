#include "tear/exec/parallel.h"
#include "tear/exec/domain.h"
#include "tear/exec/phase_timer.h"
#include "tear/exec/threads.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace tear {
namespace {

// Values whose sum depends on the order of additions (mixed magnitudes and signs).
std::vector<double> awkward_values(size_t n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = u(rng) * std::pow(10.0, double(i % 17) - 8);
  return v;
}

TEST(Exec, DeterministicSumIsBitIdenticalForOneAndTwoThreads) {
  const std::vector<double> v = awkward_values(1'000'003);
  double one = 0, two = 0;
  {
    const ThreadLimit limit(1);
    one = deterministic_sum<double>(v.size(), [&](size_t i) { return v[i]; });
  }
  {
    const ThreadLimit limit(2);
    two = deterministic_sum<double>(v.size(), [&](size_t i) { return v[i]; });
  }
  EXPECT_EQ(std::memcmp(&one, &two, sizeof(double)), 0) << one << " vs " << two;
  // The fixed order is chunk partials added in index order: reproduce it serially.
  double serial = 0;
  for (size_t c = 0; c * kReduceChunk < v.size(); ++c) {
    double part = 0;
    for (size_t i = c * kReduceChunk; i < std::min(v.size(), (c + 1) * kReduceChunk); ++i)
      part += v[i];
    serial += part;
  }
  EXPECT_EQ(std::memcmp(&one, &serial, sizeof(double)), 0);
}

TEST(Exec, ParallelMaxAndAnyVisitEveryIndexOnce) {
  const size_t n = 100'000;
  std::vector<int> visits(n, 0);
  const double best = parallel_max<double>(
      n,
      [&](size_t i) {
        ++visits[i];
        return double((i * 7919) % n);
      },
      -1.0);
  EXPECT_EQ(best, double(n - 1));
  for (int v : visits) ASSERT_EQ(v, 1);
  // parallel_any evaluates every index (callers rely on its side effects), not only until true.
  std::vector<int> seen(n, 0);
  EXPECT_TRUE(parallel_any(n, [&](size_t i) {
    ++seen[i];
    return i == 3;
  }));
  for (int v : seen) ASSERT_EQ(v, 1);
  EXPECT_FALSE(parallel_any(n, [](size_t) { return false; }));
}

TEST(Exec, ForEachColourVisitsEveryItemOnceColourByColour) {
  // Two groups, four colours: items of a colour finish before the next colour starts.
  std::vector<int> lists[2][4];
  for (int g = 0; g < 2; ++g)
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 50; ++k) lists[g][c].push_back(c * 1000 + g * 100 + k);
  std::vector<int> colour_of_visit;
  std::vector<std::vector<int>> seen(2, std::vector<int>(4000, 0));
  int current = 0;
  bool ordered = true;
  for_each_colour(
      4, 2, [&](size_t g, int c) -> const std::vector<int>& { return lists[g][c]; },
      [&](size_t g, int item) {
        const int c = item / 1000;
        if (c < current) ordered = false;
        current = std::max(current, c);
        ++seen[g][size_t(item)];
      });
  EXPECT_TRUE(ordered);
  for (int g = 0; g < 2; ++g)
    for (int c = 0; c < 4; ++c)
      for (int item : lists[g][c]) EXPECT_EQ(seen[size_t(g)][size_t(item)], 1);
}

TEST(Exec, ParallelForTilesCoversThePictureOnce) {
  const int h = 37, w = 53;
  std::vector<int> hits(size_t(h * w), 0);
  parallel_for_tiles(h, w, 16, [&](int y0, int y1, int x0, int x1) {
    EXPECT_LE(y1 - y0, 16);
    EXPECT_LE(x1 - x0, 16);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) ++hits[size_t(y * w + x)];
  });
  for (int v : hits) ASSERT_EQ(v, 1);
}

TEST(Exec, LocalDomainReductionsAreTheValues) {
  LocalDomain d;
  EXPECT_EQ(d.rank(), 0);
  EXPECT_EQ(d.ranks(), 1);
  EXPECT_EQ(d.min(2.5), 2.5);
  EXPECT_EQ(d.max(-1.0), -1.0);
  EXPECT_EQ(d.sum(3.0), 3.0);
  double v[3] = {1, 2, 3};
  d.sum(v, 3);
  EXPECT_EQ(v[2], 3.0);
}

TEST(Exec, PhaseTimerAddsElapsedTime) {
  double t = 1.0;
  { PhaseTimer timer(&t); }
  EXPECT_GE(t, 1.0);  // steady clock: never negative
}

}  // namespace
}  // namespace tear
