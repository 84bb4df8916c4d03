#include "tear/render/legend.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tear/render/color_map.h"
#include "tear/render/font.h"

namespace tear {

namespace {

constexpr Rgb8 kInk = {32, 32, 36};
constexpr int kMaxRows = 12;  // material swatches shown; the rest are summarised

Rgb8 to8(const Rgb& c) {
  auto q = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)); };
  return {q(c[0]), q(c[1]), q(c[2])};
}

// The panel's contents, laid out once for both legend_rect and draw_legend.
struct Layout {
  int s = 1, pad = 4, margin = 8;
  std::string title;
  bool bar = true;
  int bar_w = 0, bar_h = 0;
  std::string top, bottom;                        // bar labels
  std::vector<std::pair<Rgb, std::string>> rows;  // swatches
  int content_w = 0, content_h = 0;
};

Layout layout(const Legend& legend, int width, int height) {
  Layout L;
  L.s = overlay_scale(width, height);
  L.pad = 4 * L.s;
  L.margin = 8 * L.s;
  const int line = kGlyphHeight * L.s, gap = 3 * L.s;
  switch (legend.color) {
    case ColorBy::Damage:
      L.title = "DAMAGE";
      L.top = "1 CRACKED";
      L.bottom = "0 INTACT";
      break;
    case ColorBy::Velocity:
      L.title = "SPEED";
      L.top = label_number(legend.max);
      L.bottom = "0";
      break;
    case ColorBy::DrivingForce:
      L.title = "DRIVING FORCE";
      L.top = label_number(legend.max);
      L.bottom = "0";
      break;
    case ColorBy::DamageLaplacian:
      L.title = "DAMAGE LAPLACIAN";
      L.top = label_number(legend.max);
      L.bottom = label_number(-legend.max);
      break;
    case ColorBy::Material: {
      L.title = "MATERIAL";
      L.bar = false;
      const int n = int(legend.material_names.size());
      for (int i = 0; i < std::min(n, kMaxRows); ++i)
        L.rows.push_back({material_color(i), legend.material_names[size_t(i)]});
      if (n > kMaxRows) L.rows.push_back({Rgb(1, 1, 1), "+" + std::to_string(n - kMaxRows)});
      break;
    }
    case ColorBy::Fibers:
      L.title = "FIBERS";
      L.bar = false;
      L.rows = {{Rgb(1, 0, 0), "X"}, {Rgb(0, 1, 0), "Y"}};
      if (legend.dim == 3) L.rows.push_back({Rgb(0, 0, 1), "Z"});
      break;
  }
  L.content_w = text_width(L.title, L.s);
  L.content_h = line;
  if (L.bar) {
    L.bar_w = 5 * L.s;
    L.bar_h = 50 * L.s;
    const int labels = std::max(text_width(L.top, L.s), text_width(L.bottom, L.s));
    L.content_w = std::max(L.content_w, L.bar_w + gap + labels);
    L.content_h += gap + L.bar_h;
  } else {
    for (const auto& [c, name] : L.rows) {
      L.content_w = std::max(L.content_w, line + gap + text_width(name, L.s));
      L.content_h += gap + line;
    }
  }
  return L;
}

// Blends a translucent light panel over `r` (clipped to the image).
void panel(Image* image, const Rect& r) {
  for (int y = std::max(0, r.y); y < std::min(image->height, r.y + r.h); ++y)
    for (int x = std::max(0, r.x); x < std::min(image->width, r.x + r.w); ++x) {
      uint8_t* p = image->at(x, y);
      for (int c = 0; c < 3; ++c) p[c] = uint8_t((int(p[c]) + 4 * 248 + 2) / 5);
    }
}

void fill(Image* image, int x0, int y0, int w, int h, Rgb8 c) {
  for (int y = std::max(0, y0); y < std::min(image->height, y0 + h); ++y)
    for (int x = std::max(0, x0); x < std::min(image->width, x0 + w); ++x) {
      uint8_t* p = image->at(x, y);
      p[0] = c[0], p[1] = c[1], p[2] = c[2];
    }
}

}  // namespace

int overlay_scale(int width, int height) {
  return std::max(1, (std::min(height, width) + 135) / 270);
}

std::string label_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  std::string s = buf;
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

Rect legend_rect(const Legend& legend, int width, int height) {
  const Layout L = layout(legend, width, height);
  Rect r;
  r.w = L.content_w + 2 * L.pad;
  r.h = L.content_h + 2 * L.pad;
  r.x = width - L.margin - r.w;
  r.y = L.margin;
  return r;
}

void draw_legend(Image* image, const Legend& legend) {
  const Layout L = layout(legend, image->width, image->height);
  const Rect r = legend_rect(legend, image->width, image->height);
  panel(image, r);
  const int line = kGlyphHeight * L.s, gap = 3 * L.s;
  const int x = r.x + L.pad;
  int y = r.y + L.pad;
  draw_text(image, x, y, L.title, L.s, kInk);
  y += line + gap;
  if (L.bar) {
    for (int k = 0; k < L.bar_h; ++k) {
      // Top row is the map's end (cracked, fastest).
      const double t = 1 - (k + 0.5) / L.bar_h;
      const Rgb c = legend.color == ColorBy::Damage            ? damage_color(t)
                    : legend.color == ColorBy::DrivingForce    ? driving_force_color(t)
                    : legend.color == ColorBy::DamageLaplacian ? diverging_color(2 * t - 1)
                                                               : viridis_color(t);
      fill(image, x, y + k, L.bar_w, 1, to8(c));
    }
    draw_text(image, x + L.bar_w + gap, y, L.top, L.s, kInk);
    draw_text(image, x + L.bar_w + gap, y + L.bar_h - line, L.bottom, L.s, kInk);
  } else {
    for (const auto& [c, name] : L.rows) {
      fill(image, x, y, line, line, kInk);
      fill(image, x + L.s, y + L.s, line - 2 * L.s, line - 2 * L.s, to8(c));
      draw_text(image, x + line + gap, y, name, L.s, kInk);
      y += line + gap;
    }
  }
}

void draw_caption(Image* image, const std::string& text) {
  if (text.empty()) return;
  const int s = overlay_scale(image->width, image->height);
  const int pad = 4 * s, margin = 8 * s;
  const Rect r{margin, margin, text_width(text, s) + 2 * pad, kGlyphHeight * s + 2 * pad};
  panel(image, r);
  draw_text(image, r.x + pad, r.y + pad, text, s, kInk);
}

}  // namespace tear
