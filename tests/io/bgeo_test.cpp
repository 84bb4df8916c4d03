// Houdini classic BGEO: round trips, the byte layout field by field, and decode errors.
#include "tear/io/bgeo.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io_fixture.h"
#include "tear/io/point_groups.h"

namespace tear {
namespace {

// Every column of `a` is in `b` with the same values (order and integer widths may differ).
void expect_same_columns(const PointTable& a, const PointTable& b) {
  ASSERT_EQ(a.count, b.count);
  ASSERT_EQ(a.names.size(), b.names.size());
  for (const std::string& name : a.names) {
    ASSERT_TRUE(b.has(name)) << name;
    EXPECT_EQ(a.column(name), b.column(name)) << name;
  }
}

std::string decode_error(const std::string& bytes) { return error_of(decode_bgeo, bytes); }

// Big-endian readers of the raw file, independent of the codec.
int32_t be32(const std::string& s, size_t at) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data() + at);
  return int32_t(uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]);
}
int16_t be16(const std::string& s, size_t at) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data() + at);
  return int16_t(uint16_t(p[0]) << 8 | p[1]);
}
float befloat(const std::string& s, size_t at) {
  const uint32_t u = uint32_t(be32(s, at));
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

TEST(Bgeo, RoundTrips3DFrame) {
  const PointTable t = frame_like(3, 7);
  const PointTable d = decode_bgeo(encode_bgeo(t));
  expect_same_columns(t, d);
  expect_canonical_frame_columns(d);
}

TEST(Bgeo, RoundTrips2DFrame) {
  const PointTable t = frame_like(2, 5);
  const PointTable d = decode_bgeo(encode_bgeo(t));
  expect_same_columns(t, d);
  EXPECT_EQ(d.column("z"), std::vector<double>(5, 0.0));
}

TEST(Bgeo, OtherColumnsKeepTheirNames) {
  PointTable t;
  t.count = 2;
  t.add("x", ColumnType::Float32, {1, 2});
  t.add("y", ColumnType::Float32, {3, 4});  // no z: a 2D table, written with z = 0
  t.add("drive", ColumnType::Float64, {0.1, 1e-3});
  t.add("flag", ColumnType::UInt8, {255, 0});
  t.add("fx", ColumnType::Float32, {0.5, 0.25});  // a lone fiber column is a scalar
  const PointTable d = decode_bgeo(encode_bgeo(t));
  EXPECT_EQ(d.names, (std::vector<std::string>{"x", "y", "z", "drive", "flag", "fx"}));
  EXPECT_EQ(d.column("z"), std::vector<double>(2, 0.0));
  EXPECT_EQ(d.column("drive")[0], double(float(0.1)));  // 32-bit floats only
  EXPECT_EQ(d.column("flag"), (std::vector<double>{255, 0}));
  EXPECT_EQ(d.column("fx"), (std::vector<double>{0.5, 0.25}));
}

TEST(Bgeo, EmptyTableRoundTrips) {
  const PointTable t = frame_like(3, 0);
  const PointTable d = decode_bgeo(encode_bgeo(t));
  EXPECT_EQ(d.count, 0u);
  EXPECT_EQ(d.names.size(), t.names.size());
}

TEST(Bgeo, HeaderAttributesAndPointsFieldByField) {
  const PointTable t = frame_like(3, 2);
  const std::string b = encode_bgeo(t);
  ASSERT_EQ(b.substr(0, 5), "BgeoV");
  // Big-endian: the version 5 is 00 00 00 05.
  EXPECT_EQ(b.substr(5, 4), std::string("\0\0\0\x05", 4));
  EXPECT_EQ(be32(b, 5), 5);
  const int32_t expected_counts[8] = {2, 0, 0, 0, 5, 0, 0, 0};
  for (int k = 0; k < 8; ++k) EXPECT_EQ(be32(b, 9 + 4 * size_t(k)), expected_counts[k]) << k;

  struct Attr {
    std::string name;
    int size, type;
  };
  const std::vector<Attr> expected = {
      {"id", 1, 1}, {"v", 3, 5}, {"damage", 1, 0}, {"material", 1, 1}, {"fiber", 3, 5}};
  size_t at = 41;
  for (const Attr& a : expected) {
    const int16_t length = be16(b, at);
    ASSERT_EQ(length, int16_t(a.name.size())) << a.name;
    EXPECT_EQ(b.substr(at + 2, size_t(length)), a.name);
    at += 2 + size_t(length);
    EXPECT_EQ(be16(b, at), a.size) << a.name;
    EXPECT_EQ(be32(b, at + 2), a.type) << a.name;
    at += 6;
    for (int k = 0; k < a.size; ++k, at += 4) EXPECT_EQ(be32(b, at), 0) << a.name << " default";
  }
  // Per point: P (x y z w) then id, v, damage, material, fiber: 4 + 1 + 3 + 1 + 1 + 3 words.
  const size_t words = 13;
  ASSERT_EQ(b.size(), at + 2 * 4 * words + 2);
  EXPECT_EQ(befloat(b, at), 0.5f);                                 // x of point 0
  EXPECT_EQ(b.substr(at, 4), std::string("\x3f\x00\x00\x00", 4));  // 0.5f, big-endian
  EXPECT_EQ(befloat(b, at + 4), 1.0f);
  EXPECT_EQ(befloat(b, at + 8), 0.75f);
  EXPECT_EQ(befloat(b, at + 12), 1.0f);  // w
  const size_t second = at + 4 * words;
  EXPECT_EQ(befloat(b, second), 0.75f);         // x of point 1
  EXPECT_EQ(be32(b, second + 16), 1);           // id of point 1
  EXPECT_EQ(befloat(b, second + 20), -0.5f);    // vx of point 1
  EXPECT_EQ(befloat(b, second + 32), 0.0625f);  // damage of point 1
  EXPECT_EQ(be32(b, second + 36), 1);           // material of point 1
  EXPECT_EQ(befloat(b, second + 44), 0.5f);     // fy of point 1
  EXPECT_EQ(b.substr(b.size() - 2), std::string("\x00\xff", 2));
}

TEST(Bgeo, BadMagicVersionAndFormatsAreNamed) {
  std::string b = encode_bgeo(frame_like(2, 3));
  std::string bad = b;
  bad[0] = 'b';
  EXPECT_NE(decode_error(bad).find("bad BGEO: bad magic"), std::string::npos) << decode_error(bad);
  bad = b;
  bad[8] = 6;
  EXPECT_NE(decode_error(bad).find("version 6"), std::string::npos) << decode_error(bad);
  EXPECT_NE(decode_error("\x1f\x8b\x08\x00").find("gzip"), std::string::npos);
  EXPECT_NE(decode_error("\x7fNSJ....").find("new"), std::string::npos);
  bad = b;
  bad[b.size() - 1] = 0;
  EXPECT_NE(decode_error(bad).find("end bytes"), std::string::npos) << decode_error(bad);
  EXPECT_NE(decode_error(b + "x").find("unexpected bytes after the end"), std::string::npos);
}

TEST(Bgeo, EveryTruncationIsAnError) {
  const std::string b = encode_bgeo(frame_like(3, 3));
  ASSERT_EQ(decode_error(b), "no error");
  for (size_t n = 0; n < b.size(); ++n) {
    const std::string why = decode_error(b.substr(0, n));
    EXPECT_NE(why.find("truncated"), std::string::npos) << n << ": " << why;
  }
}

TEST(Bgeo, HugePointCountIsRejectedBeforeAllocating) {
  std::string b = encode_bgeo(frame_like(3, 1));
  b.replace(9, 4, std::string("\x7f\xff\xff\xff", 4));
  EXPECT_NE(decode_error(b).find("truncated"), std::string::npos) << decode_error(b);
}

// A points-only BGEO of no points and one float attribute `name` of `size` components.
std::string bgeo_with_attribute(const std::string& name, int size) {
  std::string b = "BgeoV";
  auto be = [&](uint32_t v, int bytes) {
    for (int k = bytes - 1; k >= 0; --k) b += char(v >> (8 * k) & 255);
  };
  be(5, 4);
  for (int k = 0; k < 8; ++k) be(k == 4 ? 1 : 0, 4);  // 0 points, 1 point attribute
  be(uint32_t(name.size()), 2);
  b += name;
  be(uint32_t(size), 2);
  be(0, 4);                                      // float
  for (int k = 0; k < size; ++k) be(0, 4);       // defaults
  return b + std::string("\x00\xff", 2);
}

// Found by fuzzing (tests/fuzz): each column was checked against every earlier one, so an
// attribute of 30000 components took minutes; a long name of many components also made as many
// long names. Now a hash set, and limits with clear errors.
TEST(Bgeo, WideAttributesAreReadQuicklyWithinLimits) {
  const PointTable t = decode_bgeo(bgeo_with_attribute("w", int(kMaxColumns) - 3));
  EXPECT_EQ(t.names.size(), kMaxColumns);
  EXPECT_EQ(t.names.back(), "w_" + std::to_string(kMaxColumns - 4));
  EXPECT_EQ(decode_error(bgeo_with_attribute("w", 30000)),
            "bad BGEO: attribute 'w' of 30000 components makes more than 4096 columns");
  EXPECT_EQ(decode_error(bgeo_with_attribute(std::string(2000, 'n'), 2)),
            "bad BGEO: an attribute name of 2000 bytes (at most 1024)");
}

TEST(Bgeo, EncodeNeedsPositionAndDistinctNames) {
  PointTable t;
  t.count = 1;
  t.add("damage", ColumnType::Float32, {0});
  EXPECT_THROW(encode_bgeo(t), std::runtime_error);
  PointTable clash = frame_like(3, 1);
  clash.add("v", ColumnType::Float32, {0});
  try {
    encode_bgeo(clash);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'v'"), std::string::npos) << e.what();
  }
}

TEST(PointGroups, AttributeColumnsInverseTheGrouping) {
  EXPECT_EQ(attribute_columns("P", 3, AttributeFormat::Bgeo),
            (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(attribute_columns("v", 3, AttributeFormat::Bgeo),
            (std::vector<std::string>{"vx", "vy", "vz"}));
  EXPECT_EQ(attribute_columns("velocity", 3, AttributeFormat::Vtu),
            (std::vector<std::string>{"vx", "vy", "vz"}));
  EXPECT_EQ(attribute_columns("fiber", 3, AttributeFormat::Vtu),
            (std::vector<std::string>{"fx", "fy", "fz"}));
  EXPECT_EQ(attribute_columns("v", 1, AttributeFormat::Bgeo), std::vector<std::string>{"v"});
  EXPECT_EQ(attribute_columns("Cd", 3, AttributeFormat::Bgeo),
            (std::vector<std::string>{"Cd_0", "Cd_1", "Cd_2"}));
  for (AttributeFormat f : {AttributeFormat::Bgeo, AttributeFormat::Vtu}) {
    const std::vector<PointAttribute> attrs = group_columns(frame_like(3, 2), f);
    ASSERT_EQ(attrs.size(), 6u);
    for (const PointAttribute& a : attrs)
      EXPECT_EQ(attribute_columns(a.name, int(a.components.size()), f).size(), a.components.size());
    EXPECT_TRUE(attrs[1].position);
  }
}

}  // namespace
}  // namespace tear
