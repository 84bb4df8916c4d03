// The frames of a run folder: listing, format preference, frame ranges, reading
// by extension.
#include "tear/io/frames.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tear/io/atomic_file.h"
#include "tear/io/ply.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

PointTable small_table(double x0) {
  PointTable t;
  t.count = 2;
  t.add("id", ColumnType::Int32, {0, 1});
  t.add("x", ColumnType::Float32, {x0, x0 + 1});
  return t;
}

TEST(Frames, PathHasFiveDigitsAndTheFormat) {
  EXPECT_EQ(frame_path("out", 7, "ply"), (fs::path("out") / "frames" / "00007.ply").string());
  EXPECT_EQ(frame_path("o", 123456, "ply"), (fs::path("o") / "frames" / "123456.ply").string());
}

TEST(Frames, ListSortsByFrameAndSkipsOtherFiles) {
  const fs::path dir = fs::path(testing::TempDir()) / "tear_frames_list";
  fs::remove_all(dir);
  make_directories((dir / "frames").string());
  for (int f : {10, 2, 0})
    write_file_atomic(frame_path(dir.string(), f, "ply"), encode_ply(small_table(f)));
  write_file_atomic((dir / "frames" / "notes.txt").string(), "x");
  write_file_atomic((dir / "frames" / "00003.png").string(), "x");
  const std::vector<FrameFile> frames = list_frames(dir.string());
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].frame, 0);
  EXPECT_EQ(frames[1].frame, 2);
  EXPECT_EQ(frames[2].frame, 10);
  EXPECT_EQ(frames[2].format, "ply");
  EXPECT_DOUBLE_EQ(read_frame(frames[2].path).column("x")[1], 11);
  fs::remove_all(dir);
}

TEST(Frames, MissingFolderAndUnknownFormatAreClearErrors) {
  try {
    list_frames("/nonexistent/run");
    FAIL();
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run: no frames/ folder"), std::string::npos);
  }
  EXPECT_THROW(read_frame("a/frames/00001.xyz"), std::runtime_error);
  EXPECT_THROW(encode_points(small_table(0), "xyz"), std::runtime_error);
}

TEST(Frames, RangesParse) {
  FrameRange all = parse_frame_range("");
  EXPECT_TRUE(all.contains(0) && all.contains(99999));
  FrameRange ab = parse_frame_range("3:5");
  EXPECT_FALSE(ab.contains(2));
  EXPECT_TRUE(ab.contains(3) && ab.contains(5));
  EXPECT_FALSE(ab.contains(6));
  FrameRange from = parse_frame_range("4:");
  EXPECT_TRUE(from.contains(1000) && !from.contains(3));
  FrameRange to = parse_frame_range(":4");
  EXPECT_TRUE(to.contains(0) && to.contains(4) && !to.contains(5));
  FrameRange one = parse_frame_range("7");
  EXPECT_TRUE(one.contains(7) && !one.contains(6) && !one.contains(8));
  for (const char *bad : {"5:3", "a:b", "1:2:3", "-1", "x"})
    EXPECT_THROW(parse_frame_range(bad), std::runtime_error) << bad;
}

}  // namespace
}  // namespace tear
