// PNG encoding, the bitmap font, the colour maps and the video encoder.
#include "tear/render/image.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>

#include "tear/io/atomic_file.h"
#include "tear/render/color_map.h"
#include "tear/render/font.h"
#include "tear/render/video.h"

namespace tear {
namespace {

namespace fs = std::filesystem;

Image gradient(int w, int h) {
  Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = im.at(x, y);
      p[0] = uint8_t(x * 7), p[1] = uint8_t(y * 13), p[2] = uint8_t(x ^ y);
    }
  return im;
}

TEST(Png, RoundTripsThroughLibpng) {
  const Image im = gradient(37, 21);
  const std::string bytes = encode_png(im);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  const Image back = decode_png(bytes);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 21);
  EXPECT_EQ(back.rgb, im.rgb);
  EXPECT_EQ(encode_png(im), bytes);  // no time stamp: same bytes every time
}

TEST(Png, MalformedInputIsAnError) {
  EXPECT_THROW(decode_png("not a png at all"), std::runtime_error);
  const std::string bytes = encode_png(gradient(20, 20));
  try {
    decode_png(bytes.substr(0, bytes.size() / 2));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("PNG decoding failed"), std::string::npos) << e.what();
  }
}

TEST(Font, GlyphsAreDistinctAndCaseInsensitive) {
  const std::string chars = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ.-+:_/()=%? ";
  std::set<std::array<uint8_t, 7>> seen;
  for (char c : chars) {
    const auto& g = glyph(c);
    EXPECT_TRUE(seen.insert(g).second) << "glyph of '" << c << "' repeats another";
    for (uint8_t row : g) EXPECT_LT(row, 32) << c;  // five columns
  }
  EXPECT_EQ(glyph('a'), glyph('A'));
  EXPECT_EQ(glyph('~'), glyph('?'));
  EXPECT_EQ(text_width("AB", 2), 22);
  Image im(40, 20);
  draw_text(&im, 1, 1, "8", 1, {255, 255, 255});
  int lit = 0;
  for (uint8_t v : im.rgb) lit += v == 255;
  EXPECT_EQ(lit, 3 * 17);  // the pixels of an 8
}

TEST(ColourMaps, DamageDarkensFromIntactToCrackedAndViridisEnds) {
  auto luma = [](const Rgb& c) {
    return 0.2126 * srgb_to_linear(c[0]) + 0.7152 * srgb_to_linear(c[1]) +
           0.0722 * srgb_to_linear(c[2]);
  };
  double prev = 2;
  for (int k = 0; k <= 20; ++k) {
    const double l = luma(damage_color(k / 20.0));
    EXPECT_LT(l, prev) << k;
    prev = l;
  }
  EXPECT_GT(damage_color(1)[0], 2 * damage_color(1)[1]);  // cracked is red
  EXPECT_NEAR(viridis_color(0)[0], 0x44 / 255.0, 1e-6);
  EXPECT_NEAR(viridis_color(1)[1], 0xe7 / 255.0, 1e-6);
  EXPECT_EQ(viridis_color(2), viridis_color(1));  // clamped
  EXPECT_NE(material_color(0), material_color(1));
  EXPECT_EQ(material_color(10), material_color(0));
  EXPECT_EQ(fiber_color(0, -1, 0), Rgb(0, 1, 0));
  for (float c : {0.0f, 0.02f, 0.5f, 1.0f}) EXPECT_NEAR(linear_to_srgb(srgb_to_linear(c)), c, 1e-5);
}

bool have_ffmpeg() { return std::system("ffmpeg -version > /dev/null 2>&1") == 0; }

TEST(Video, EncodesNonContiguousFramesWithFfmpeg) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not on PATH";
  const fs::path dir = fs::path(testing::TempDir()) / "tear_video_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<std::string> frames;
  for (int f : {0, 3, 9}) {  // gaps, as output.every leaves them; odd size gets padded
    frames.push_back((dir / ("0000" + std::to_string(f) + ".png")).string());
    write_file_atomic(frames.back(), encode_png(gradient(33, 17)));
  }
  const std::string out = (dir / "preview.mp4").string();
  ASSERT_TRUE(make_video(frames, 24, out, 1));
  const std::string mp4 = read_file(out);
  ASSERT_GT(mp4.size(), 100u);
  EXPECT_EQ(mp4.substr(4, 4), "ftyp");
  // Nothing left behind but the inputs and the video.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 4);
  fs::remove_all(dir);
}

TEST(Video, MissingFfmpegWritesNothing) {
  const fs::path dir = fs::path(testing::TempDir()) / "tear_video_missing";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string png = (dir / "00000.png").string();
  write_file_atomic(png, encode_png(gradient(8, 8)));
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", "/nonexistent-tear-test", 1);
  bool made = true;
  EXPECT_NO_THROW(made = make_video({png}, 24, (dir / "preview.mp4").string()));
  setenv("PATH", saved.c_str(), 1);
  EXPECT_FALSE(made);
  EXPECT_FALSE(fs::exists(dir / "preview.mp4"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tear
