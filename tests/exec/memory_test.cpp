#include "tear/exec/memory.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace tear {
namespace {

// Growing one element at a time through reserve_large reallocates a logarithmic number of
// times (capacity at least doubles), keeps the values, and large (advised) storage holds and
// reads back like any other.
TEST(Memory, ReserveLargeGrowsGeometricallyAndKeepsValues) {
  std::vector<double> v;
  int reallocations = 0;
  const double* data = nullptr;
  for (size_t i = 0; i < 3'000'000; ++i) {  // 24 MB at the end: advised
    reserve_large(&v, i + 1);
    if (v.data() != data) ++reallocations, data = v.data();
    v.push_back(double(i) * 0.5);
  }
  EXPECT_LE(reallocations, 24);
  for (size_t i = 0; i < v.size(); i += 9973) EXPECT_EQ(v[i], double(i) * 0.5);
  EXPECT_EQ(v.back(), double(v.size() - 1) * 0.5);

  std::string s = "keep";
  reserve_large(&s, 8u << 20);
  EXPECT_EQ(s, "keep");
  EXPECT_GE(s.capacity(), size_t(8u << 20));
  s.resize(8u << 20, 'x');
  EXPECT_EQ(s.substr(0, 4), "keep");
  EXPECT_EQ(s.back(), 'x');
}

// Small or unaligned ranges are left alone, without error.
TEST(Memory, AdviceOnAnyRangeIsHarmless) {
  std::vector<char> a(100, 'a');
  advise_huge_pages(a.data(), a.size());
  advise_huge_pages(nullptr, 0);
  std::vector<char> b(5u << 20, 'b');
  advise_huge_pages(b.data() + 1, b.size() - 1);
  EXPECT_EQ(a[99], 'a');
  EXPECT_EQ(b[b.size() / 2], 'b');
}

}  // namespace
}  // namespace tear
