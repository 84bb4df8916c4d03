#include "tear/io/atomic_file.h"
#include "tear/io/binary.h"
#include "tear/io/ply.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "io_fixture.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("tear_io_test_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  size_t entries() const {
    return size_t(std::distance(fs::directory_iterator(path_), fs::directory_iterator()));
  }

 private:
  fs::path path_;
};

PointTable sample_table() {
  PointTable t;
  t.count = 3;
  t.add("id", ColumnType::Int32, {0, -7, 2147483647});
  t.add("x", ColumnType::Float32, {0.1, -2.5, 1e10});
  t.add("m", ColumnType::UInt8, {0, 255, 17});
  t.add("d", ColumnType::Float64, {0.1, -1e-300, 3.25});
  return t;
}

TEST(Ply, HeaderIsExact) {
  const std::string bytes = encode_ply(sample_table());
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex 3\n"
      "property int id\nproperty float x\nproperty uchar m\nproperty double d\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  EXPECT_EQ(bytes.size(), header.size() + 3 * (4 + 4 + 1 + 8));
}

TEST(Ply, RoundTripKeepsEveryType) {
  const PointTable t = decode_ply(encode_ply(sample_table()));
  ASSERT_EQ(t.count, 3u);
  EXPECT_EQ(t.names, (std::vector<std::string>{"id", "x", "m", "d"}));
  EXPECT_EQ(t.column("id"), (std::vector<double>{0, -7, 2147483647}));
  EXPECT_EQ(t.column("x")[0], double(0.1f));  // float32 rounding
  EXPECT_EQ(t.column("x")[2], double(1e10f));
  EXPECT_EQ(t.column("m"), (std::vector<double>{0, 255, 17}));
  EXPECT_EQ(t.column("d"), (std::vector<double>{0.1, -1e-300, 3.25}));
  EXPECT_EQ(t.types[2], ColumnType::UInt8);
}

TEST(Ply, ReadsAscii) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty int32 n\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n1.5 3\n-2 4\n";
  const PointTable t = decode_ply(text);
  EXPECT_EQ(t.column("x"), (std::vector<double>{1.5, -2}));
  EXPECT_EQ(t.column("n"), (std::vector<double>{3, 4}));
}

TEST(Ply, RejectsMalformedInput) {
  const std::string good = encode_ply(sample_table());
  auto message = [](const std::string& bytes) { return error_of(decode_ply, bytes); };
  EXPECT_NE(message(good.substr(0, good.size() - 1)).find("truncated"), std::string::npos);
  EXPECT_NE(message("PLY\n").find("does not start"), std::string::npos);
  EXPECT_NE(message("ply\nformat ascii 1.0\nelement vertex 1\n").find("end_header"),
            std::string::npos);
  EXPECT_NE(message("ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n")
                .find("unsupported format"),
            std::string::npos);
  EXPECT_NE(message("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar int i\n"
                    "end_header\n")
                .find("list"),
            std::string::npos);
  EXPECT_NE(message("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n1\n")
                .find("unknown property type"),
            std::string::npos);
  EXPECT_THROW(sample_table().column("nope"), std::runtime_error);
  PointTable t;
  t.count = 2;
  EXPECT_THROW(t.add("x", ColumnType::Float32, {1}), std::runtime_error);
}

TEST(AtomicFile, ReplacesContentAndLeavesNoTemporary) {
  TempDir dir;
  const std::string path = dir.file("a.txt");
  write_file_atomic(path, "first");
  write_file_atomic(path, "second");
  EXPECT_EQ(read_file(path), "second");
  EXPECT_EQ(dir.entries(), 1u);
  write_lines_atomic(dir.file("s.jsonl"), {"{\"a\":1}", "{\"a\":2}"});
  EXPECT_EQ(read_file(dir.file("s.jsonl")), "{\"a\":1}\n{\"a\":2}\n");
}

TEST(AtomicFile, ErrorsNameThePath) {
  TempDir dir;
  const std::string missing = dir.file("no/such/folder/f.bin");
  try {
    write_file_atomic(missing, "x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_file(dir.file("absent")), std::runtime_error);
  make_directories(dir.file("x/y/z"));
  EXPECT_TRUE(fs::is_directory(dir.file("x/y/z")));
}

// A writer's pieces (copied values and memory referenced in place) read as one array: the
// checksum fed piece by piece at any boundaries equals the one-shot checksum, and a file
// written from the pieces holds the joined bytes.
TEST(Binary, PiecesChecksumAndFileEqualTheJoinedBytes) {
  std::string field(1003, '\0');
  for (size_t i = 0; i < field.size(); ++i) field[i] = char(i * 37 + 11);
  for (size_t head = 0; head < 17; ++head) {
    ByteWriter w;
    w.put_bytes(std::string(head, 'h'));
    w.put_view(field.data(), field.size());
    w.put<int32_t>(7);
    w.put_view(field.data() + 5, head);  // empty when head = 0
    w.put_view(field.data(), 3);
    const std::string joined = w.bytes();
    ASSERT_EQ(joined.size(), w.size());
    EXPECT_EQ(joined, std::string(head, 'h') + field + std::string("\x07\0\0\0", 4) +
                          field.substr(5, head) + field.substr(0, 3));
    ByteWriter with_sum = w;
    put_checksum(&with_sum);
    std::string expected = joined;
    append_checksum(&expected);
    EXPECT_EQ(with_sum.bytes(), expected) << head;
    EXPECT_TRUE(checksum_matches(with_sum.bytes()));
    Checksum64 bytewise(joined.size());
    for (char c : joined) bytewise.add(&c, 1);
    EXPECT_EQ(bytewise.finish(), checksum64(joined.data(), joined.size()));
  }
  TempDir dir;
  ByteWriter w;
  w.put<double>(1.5);
  w.put_view(field.data(), field.size());
  write_file_atomic(dir.file("pieces.bin"), w);
  EXPECT_EQ(read_file(dir.file("pieces.bin")), w.bytes());
}

TEST(Binary, RoundTripAndTruncation) {
  ByteWriter w;
  w.put<int32_t>(-5);
  w.put_vector(std::vector<double>{1.5, 2.5});
  const std::string bytes = w.bytes();
  ByteReader r(bytes);
  EXPECT_EQ(r.get<int32_t>(), -5);
  std::vector<double> v;
  r.get_vector(&v);
  EXPECT_EQ(v, (std::vector<double>{1.5, 2.5}));
  EXPECT_TRUE(r.at_end());
  const std::string cut = bytes.substr(0, bytes.size() - 1);
  ByteReader r2(cut);
  r2.get<int32_t>();
  EXPECT_THROW(r2.get_vector(&v), std::runtime_error);
}

}  // namespace
}  // namespace tear
