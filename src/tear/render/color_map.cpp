#include "tear/render/color_map.h"

#include <algorithm>
#include <cmath>

namespace tear {

namespace {

// The maps' nine equally spaced sRGB stops (0xRRGGBB).
constexpr unsigned kYlOrRd[9] = {0xffffcc, 0xffeda0, 0xfed976, 0xfeb24c, 0xfd8d3c,
                                 0xfc4e2a, 0xe31a1c, 0xbd0026, 0x800026};
constexpr unsigned kYlGnBu[9] = {0xffffd9, 0xedf8b1, 0xc7e9b4, 0x7fcdbb, 0x41b6c4,
                                 0x1d91c0, 0x225ea8, 0x253494, 0x081d58};
constexpr unsigned kBuRd[9] = {0x2166ac, 0x4393c3, 0x92c5de, 0xd1e5f0, 0xf7f7f7,
                               0xfddbc7, 0xf4a582, 0xd6604d, 0xb2182b};  // RdBu reversed
constexpr unsigned kViridis[9] = {0x440154, 0x472d7b, 0x3b528b, 0x2c728e, 0x21918c,
                                  0x28ae80, 0x5ec962, 0xaddc30, 0xfde725};

Rgb hex_rgb(unsigned c) {
  return Rgb(float((c >> 16) & 255) / 255, float((c >> 8) & 255) / 255, float(c & 255) / 255);
}

// Piecewise-linear through the stops.
Rgb ramp(const unsigned (&stops)[9], double t) {
  constexpr int n = 9;
  if (!(t >= 0)) t = 0;  // NaN too
  if (t > 1) t = 1;
  const double x = t * (n - 1);
  const int i = std::min(int(x), n - 2);
  const float w = float(x - i);
  return (1 - w) * hex_rgb(stops[i]) + w * hex_rgb(stops[i + 1]);
}

}  // namespace

Rgb damage_color(double d) { return ramp(kYlOrRd, d); }

Rgb driving_force_color(double t) { return ramp(kYlGnBu, t); }

Rgb diverging_color(double v) { return ramp(kBuRd, std::isfinite(v) ? 0.5 + 0.5 * v : 0.5); }

Rgb viridis_color(double t) { return ramp(kViridis, t); }

Rgb material_color(int index) {
  static const unsigned kTableau10[] = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f,
                                        0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac};
  return hex_rgb(kTableau10[((index % 10) + 10) % 10]);
}

Rgb fiber_color(double fx, double fy, double fz) {
  auto channel = [](double v) { return float(std::min(1.0, std::abs(std::isfinite(v) ? v : 0))); };
  return Rgb(channel(fx), channel(fy), channel(fz));
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

Eigen::Vector3f linear_rgb(const Rgb& c) {
  return Eigen::Vector3f(srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2]));
}

float linear_to_srgb(float c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return 1;
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

}  // namespace tear
