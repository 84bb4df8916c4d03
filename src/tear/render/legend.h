// render/: the legend (colour bar or swatches with the field's name) and the caption drawn
// into a rendered picture.
#pragma once

#include <string>
#include <vector>

#include "tear/render/render.h"

namespace tear {

struct Legend {
  ColorBy color = ColorBy::Damage;
  double max = 1;  // velocity, driving force: top of the bar; damage Laplacian: its ends +-max
  int dim = 3;                              // fibers: x y, or x y z
  std::vector<std::string> material_names;  // material: one swatch per name
};

struct Rect {
  int x = 0, y = 0, w = 0, h = 0;
};

// Font scale (pixels per font pixel) for a picture of this size.
int overlay_scale(int width, int height);
// Where draw_legend draws (top right), for a picture of this size.
Rect legend_rect(const Legend& legend, int width, int height);
void draw_legend(Image* image, const Legend& legend);
// `text` in a small panel at the top left; nothing for empty text.
void draw_caption(Image* image, const std::string& text);

// "0.25", "1.5E+03": a number for a label in three significant digits.
std::string label_number(double v);

}  // namespace tear
