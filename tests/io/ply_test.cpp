#include "tear/io/ply.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io_fixture.h"

namespace tear {
namespace {

// The error message decode_ply gives for `bytes`, or "no error".
std::string decode_error(const std::string& bytes) { return error_of(decode_ply, bytes); }

template <class T>
void append_le(std::string* out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (__BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__)
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out->append(reinterpret_cast<const char*>(b), sizeof(T));
}

TEST(Ply, FrameHeaderIsExact) {
  const PointTable t = frame_like(3, 2);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex 2\n"
      "property int id\nproperty float x\nproperty float y\nproperty float z\n"
      "property float vx\nproperty float vy\nproperty float vz\nproperty float damage\n"
      "property uchar material\nproperty float fx\nproperty float fy\nproperty float fz\n"
      "end_header\n";
  const std::string bytes = encode_ply(t);
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  EXPECT_EQ(bytes.size(), header.size() + 2 * (4 + 10 * 4 + 1));
}

TEST(Ply, EncodesRowsLittleEndianVertexMajor) {
  PointTable t;
  t.count = 2;
  t.add("id", ColumnType::Int32, {1, -2});
  t.add("x", ColumnType::Float32, {1.0, -2.0});
  t.add("m", ColumnType::UInt8, {200, 3});
  t.add("d", ColumnType::Float64, {2.0, 0.0});
  const std::string bytes = encode_ply(t);
  const std::string body = bytes.substr(bytes.find("end_header\n") + 11);
  const unsigned char expected[] = {
      0x01, 0x00, 0x00, 0x00,  0x00, 0x00, 0x80, 0x3F,  0xC8,  // id 1, x 1.0f, m 200
      0, 0, 0, 0, 0, 0, 0x00, 0x40,                          // d 2.0
      0xFE, 0xFF, 0xFF, 0xFF,  0x00, 0x00, 0x00, 0xC0,  0x03,  // id -2, x -2.0f, m 3
      0, 0, 0, 0, 0, 0, 0, 0};                               // d 0.0
  ASSERT_EQ(body.size(), sizeof(expected));
  for (size_t i = 0; i < sizeof(expected); ++i)
    EXPECT_EQ(static_cast<unsigned char>(body[i]), expected[i]) << "byte " << i;
}

TEST(Ply, RoundTripIsExactUpToFloat32Rounding) {
  const size_t n = 1000;
  std::vector<double> id(n), x(n), m(n), d(n);
  for (size_t i = 0; i < n; ++i) {
    id[i] = double(int64_t(i) * 2147483 - 1073741824);
    x[i] = 1.0 / double(i + 3) - 0.25;
    m[i] = double(i % 256);
    d[i] = std::ldexp(1.0 / 3.0, int(i % 200) - 100);
  }
  PointTable t;
  t.count = n;
  t.add("id", ColumnType::Int32, id);
  t.add("x", ColumnType::Float32, x);
  t.add("m", ColumnType::UInt8, m);
  t.add("d", ColumnType::Float64, d);
  const PointTable r = decode_ply(encode_ply(t));
  ASSERT_EQ(r.count, n);
  EXPECT_EQ(r.names, t.names);
  EXPECT_EQ(r.types, t.types);
  EXPECT_EQ(r.column("id"), id);
  EXPECT_EQ(r.column("m"), m);
  EXPECT_EQ(r.column("d"), d);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(r.column("x")[i], double(float(x[i]))) << i;
  EXPECT_NE(r.column("x")[0], x[0]);  // 1/3 - 1/4 is not a float: rounding did happen
}

TEST(Ply, EmptyTableRoundTrips) {
  PointTable t;
  t.add("id", ColumnType::Int32, {});
  const PointTable r = decode_ply(encode_ply(t));
  EXPECT_EQ(r.count, 0u);
  EXPECT_EQ(r.names, std::vector<std::string>{"id"});
  EXPECT_TRUE(r.column("id").empty());
}

TEST(Ply, DecodesEveryScalarTypeName) {
  const char* kOld[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
  const char* kSized[] = {"int8",  "uint8",  "int16",   "uint16",
                          "int32", "uint32", "float32", "float64"};
  for (const char* const* names : {kOld, kSized}) {
    std::string bytes = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n";
    for (int k = 0; k < 8; ++k)
      bytes += "property " + std::string(names[k]) + " p" + std::to_string(k) + "\n";
    bytes += "end_header\n";
    append_le<int8_t>(&bytes, -128);
    append_le<uint8_t>(&bytes, 255);
    append_le<int16_t>(&bytes, -32768);
    append_le<uint16_t>(&bytes, 65535);
    append_le<int32_t>(&bytes, -2147483647 - 1);
    append_le<uint32_t>(&bytes, 4294967295u);
    append_le<float>(&bytes, 0.1f);
    append_le<double>(&bytes, 0.1);
    const PointTable t = decode_ply(bytes);
    ASSERT_EQ(t.count, 1u) << names[0];
    const double expected[] = {-128,        255,        -32768,       65535,
                               -2147483648.0, 4294967295.0, double(0.1f), 0.1};
    for (int k = 0; k < 8; ++k)
      EXPECT_EQ(t.column("p" + std::to_string(k))[0], expected[k]) << names[k];
    EXPECT_EQ(t.types[1], ColumnType::UInt8);
    EXPECT_EQ(t.types[4], ColumnType::Int32);
    EXPECT_EQ(t.types[5], ColumnType::Float64);  // uint32 beyond 2^31 survives re-encoding
    EXPECT_EQ(t.types[6], ColumnType::Float32);
    EXPECT_EQ(t.types[7], ColumnType::Float64);
  }
}

TEST(Ply, ReadsAsciiWithCrlfCommentsAndEmptyElements) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\ncomment the word end_header in a comment\r\n"
      "obj_info made by hand\r\nelement vertex 3\r\nproperty double x\r\nproperty uchar m\r\n"
      "element face 0\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
      "1.5 7\r\n-2e-3 0\r\n  1e300   255  \r\n";
  const PointTable t = decode_ply(text);
  ASSERT_EQ(t.count, 3u);
  EXPECT_EQ(t.column("x"), (std::vector<double>{1.5, -2e-3, 1e300}));
  EXPECT_EQ(t.column("m"), (std::vector<double>{7, 0, 255}));
}

TEST(Ply, RejectsCorruptInputWithTheReason) {
  const std::string bin = "ply\nformat binary_little_endian 1.0\n";
  const std::string asc = "ply\nformat ascii 1.0\n";
  struct Case {
    std::string bytes, reason;
  };
  const Case cases[] = {
      // A huge count must be refused before anything is allocated.
      {bin + "element vertex 99999999999999999\nproperty float x\nend_header\n" +
           std::string(8, '\0'),
       "truncated: 99999999999999999 vertices of 4 bytes, found 8 bytes"},
      {bin + "element vertex 2\nproperty double x\nend_header\n" + std::string(15, '\0'),
       "truncated: 2 vertices of 8 bytes, found 15 bytes"},
      {asc + "element vertex 2\nproperty float x\nproperty float y\nend_header\n" +
           "1 2\n3          \n",
       "truncated or non-numeric ascii data at vertex 1, property 'y'"},
      {asc + "element vertex 1\nproperty float x\nend_header\nabc\n", "non-numeric"},
      {asc + "element vertex 1\nproperty float x\nend_header\n1.5x\n", "non-numeric"},
      {asc + "element vertex 99999999\nproperty float x\nend_header\n1 2 3\n", "truncated"},
      {asc + "element vertex -1\nend_header\n", "element 'vertex' without a valid count"},
      {asc + "element vertex many\nend_header\n", "without a valid count"},
      {asc + "element vertex\nend_header\n", "without a valid count"},
      {asc + "property float x\nelement vertex 0\nend_header\n", "property before any element"},
      {asc + "element vertex 0\nproperty float x\nproperty int x\nend_header\n",
       "property 'x' appears twice"},
      {asc + "element vertex 0\nproperty float\nend_header\n", "property without a name"},
      {asc + "element vertex 0\nproprety float x\nend_header\n",
       "unexpected header line 'proprety float x'"},
      {asc + "element vertex 0\nproperty list uchar int i\nend_header\n",
       "list properties are not supported"},
      {asc + "element vertex 0\nproperty half x\nend_header\n", "unknown property type 'half'"},
      {asc + "element vertex 1\nelement face 1\nproperty list uchar int i\nend_header\n" +
           "1\n3 0 0 0\n",
       "element 'face' has data; only 'vertex' is supported"},
      {asc + "element vertex 0\nelement vertex 0\nend_header\n", "two vertex elements"},
      {asc + "element face 0\nend_header\n", "no vertex element"},
      {"ply\nelement vertex 0\nend_header\n", "no format line"},
      {asc + "format ascii 1.0\nelement vertex 0\nend_header\n", "two format lines"},
      {"ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n",
       "unsupported format 'binary_big_endian'"},
      {asc + "element vertex 0\n", "no end_header line"},
      {asc + "element vertex 0\nend_header", "no line break after end_header"},
      {"PLY\nformat ascii 1.0\n", "does not start with 'ply'"},
      {"plyformat ascii 1.0\n", "does not start with 'ply'"},
      {"", "does not start with 'ply'"},
  };
  for (const Case& c : cases) {
    const std::string message = decode_error(c.bytes);
    EXPECT_EQ(message.rfind("bad PLY: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.reason), std::string::npos)
        << "got: " << message << "\nwanted: " << c.reason;
  }
}

// Found by fuzzing (tests/fuzz): a vertex element of no properties and a huge count made the
// reader allocate a column of that many rows (8 EB: an allocation failure) and then loop over them.
TEST(Ply, RowsWithoutPropertiesAreRefusedWithoutAllocating) {
  EXPECT_EQ(decode_error("ply\nformat ascii 1.0\nelement vertex 999999999999999999\nend_header\n"),
            "bad PLY: element 'vertex' has 999999999999999999 rows but no properties");
  EXPECT_EQ(decode_ply("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n").count, 0u);
}

// Found by fuzzing: an ascii value was kept as written whatever its property's type, so a uchar
// column could hold 300 or 1.5 (which encode_ply then converted with undefined behaviour) and a
// float column more digits than a float has (a round trip through encode_ply changed it).
TEST(Ply, AsciiValuesAreOfTheirPropertysType) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
  const PointTable t = decode_ply(head + "property int i\nproperty uchar m\nend_header\n"
                                         "-2e-3 -2147483648 255\n");
  EXPECT_EQ(t.column("x")[0], double(-2e-3f));  // rounded to float, as a binary file holds it
  EXPECT_EQ(t.column("i")[0], -2147483648.0);
  EXPECT_EQ(t.column("m")[0], 255);
  EXPECT_EQ(decode_ply(encode_ply(t)).columns, t.columns);
  EXPECT_EQ(decode_error(head + "property uchar m\nend_header\n0 300\n"),
            "bad PLY: ascii value '300' at vertex 0, property 'm' is not a uint8");
  EXPECT_EQ(decode_error(head + "property int i\nend_header\n0 1.5\n"),
            "bad PLY: ascii value '1.5' at vertex 0, property 'i' is not a int32");
  EXPECT_EQ(decode_error(head + "property short s\nend_header\n0 nan\n"),
            "bad PLY: ascii value 'nan' at vertex 0, property 's' is not a int16");
  EXPECT_EQ(decode_error(head + "end_header\n1e39\n"),
            "bad PLY: ascii value '1e39' at vertex 0, property 'x' is not a float32");
  EXPECT_EQ(decode_ply(head + "end_header\ninf\n").column("x")[0], HUGE_VAL);
}

TEST(Ply, ColumnOfMissingNameThrowsNamingIt) {
  PointTable t;
  t.count = 1;
  t.add("damage", ColumnType::Float32, {0.25});
  EXPECT_TRUE(t.has("damage"));
  EXPECT_FALSE(t.has("Damage"));
  EXPECT_EQ(t.column("damage"), std::vector<double>{0.25});
  try {
    t.column("fiber");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "no column 'fiber'");
  }
  EXPECT_THROW(t.add("damage", ColumnType::Float64, {1}), std::runtime_error);
  EXPECT_EQ(t.names.size(), 1u);
}

TEST(Ply, EncodeRejectsColumnsOfTheWrongLength) {
  PointTable t;
  t.count = 3;
  t.add("x", ColumnType::Float32, {1, 2, 3});
  t.columns[0].pop_back();  // bypassing add()
  EXPECT_THROW(encode_ply(t), std::runtime_error);
  t.columns[0].push_back(3);
  t.types.pop_back();
  EXPECT_THROW(encode_ply(t), std::runtime_error);
}

}  // namespace
}  // namespace tear
