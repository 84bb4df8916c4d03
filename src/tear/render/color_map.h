// render/: colour maps of the fields a frame carries, and the sRGB transfer curve.
#pragma once

#include <Eigen/Core>

namespace tear {

// Display (sRGB-encoded) colour, each channel in [0, 1].
using Rgb = Eigen::Vector3f;

// Damage in [0, 1], intact to cracked: ColorBrewer's sequential YlOrRd (pale yellow, orange,
// deep red), perceptually ordered (lightness falls monotonically).
Rgb damage_color(double d);
// Driving force from 0 to the map's top, t in [0, 1]: ColorBrewer's sequential YlGnBu (pale
// yellow, green, deep blue), lightness falling like damage's map but in other hues.
Rgb driving_force_color(double t);
// A signed value over the map's range [-1, 1] (damage Laplacian): ColorBrewer's diverging RdBu,
// blue below 0, near white at 0, red above.
Rgb diverging_color(double v);
// t in [0, 1] on viridis (perceptually uniform, readable in grey and for colour-blind eyes).
Rgb viridis_color(double t);
// A fixed palette by material index (Tableau 10, repeating after 10).
Rgb material_color(int index);
// Absolute fiber components as red, green, blue (x, y, z).
Rgb fiber_color(double fx, double fy, double fz);

// The sRGB transfer curve (IEC 61966-2-1) and its inverse, per channel.
float srgb_to_linear(float c);
float linear_to_srgb(float c);
// srgb_to_linear of each channel.
Eigen::Vector3f linear_rgb(const Rgb& c);

}  // namespace tear
