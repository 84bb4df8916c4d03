#include "tear/render/color_map.h"

#include <algorithm>
#include <cmath>

namespace tear {

namespace {

// Piecewise-linear through `n` equally spaced sRGB stops (0xRRGGBB).
Rgb ramp(const unsigned* stops, int n, double t) {
  if (!(t >= 0)) t = 0;  // NaN too
  if (t > 1) t = 1;
  const double x = t * (n - 1);
  const int i = std::min(int(x), n - 2);
  const float w = float(x - i);
  auto rgb = [](unsigned c) {
    return Rgb(float((c >> 16) & 255) / 255, float((c >> 8) & 255) / 255, float(c & 255) / 255);
  };
  return (1 - w) * rgb(stops[i]) + w * rgb(stops[i + 1]);
}

}  // namespace

Rgb damage_color(double d) {
  static const unsigned kYlOrRd[] = {0xffffcc, 0xffeda0, 0xfed976, 0xfeb24c, 0xfd8d3c,
                                     0xfc4e2a, 0xe31a1c, 0xbd0026, 0x800026};
  return ramp(kYlOrRd, 9, d);
}

Rgb viridis_color(double t) {
  static const unsigned kViridis[] = {0x440154, 0x472d7b, 0x3b528b, 0x2c728e, 0x21918c,
                                      0x28ae80, 0x5ec962, 0xaddc30, 0xfde725};
  return ramp(kViridis, 9, t);
}

Rgb material_color(int index) {
  static const unsigned kTableau10[] = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f,
                                        0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac};
  const unsigned c = kTableau10[((index % 10) + 10) % 10];
  return Rgb(float((c >> 16) & 255) / 255, float((c >> 8) & 255) / 255, float(c & 255) / 255);
}

Rgb fiber_color(double fx, double fy, double fz) {
  auto channel = [](double v) { return float(std::min(1.0, std::abs(std::isfinite(v) ? v : 0))); };
  return Rgb(channel(fx), channel(fy), channel(fz));
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return 1;
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

}  // namespace tear
