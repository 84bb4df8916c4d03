// render/: a 5x7 bitmap font for the legend and caption: digits, upper-case letters (lower case
// is drawn as upper case) and . - + : _ / ( ) = % ? and space; other characters draw as '?'.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "tear/render/image.h"

namespace tear {

using Rgb8 = std::array<uint8_t, 3>;

constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// Rows top to bottom, bit 4 the leftmost column.
const std::array<uint8_t, 7>& glyph(char c);

// Width in pixels of `text` drawn at `scale` (each font pixel a scale x scale block).
int text_width(const std::string& text, int scale);
// Draws `text` with its top-left corner at (x, y); pixels outside the image are skipped.
void draw_text(Image* image, int x, int y, const std::string& text, int scale, Rgb8 color);

}  // namespace tear
