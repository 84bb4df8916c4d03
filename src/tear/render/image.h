// render/: 8-bit RGB pictures and their PNG encoding (libpng).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tear {

// Display-referred (sRGB-encoded) 8-bit RGB, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 bytes per pixel

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0) {}
  uint8_t* at(int x, int y) { return &rgb[3 * (size_t(y) * size_t(width) + size_t(x))]; }
  const uint8_t* at(int x, int y) const {
    return &rgb[3 * (size_t(y) * size_t(width) + size_t(x))];
  }
};

// PNG bytes (8-bit RGB, no time stamp: the same image always gives the same bytes).
std::string encode_png(const Image& image);
// Any PNG libpng reads, as 8-bit RGB (alpha dropped, grey expanded); throws std::runtime_error
// with libpng's reason on malformed input.
Image decode_png(const std::string& bytes);

// The libpng version this build was compiled against (`tear info`).
const char* libpng_version();

}  // namespace tear
