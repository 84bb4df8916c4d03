// damage/: figures of a crack pattern in rest (material) space, for tests and for people:
// which way a body tore and how wide its cracked bands are. Pure geometry of the particles'
// rest positions and damage; the frames of a run hold both (frame 0's positions, a later
// frame's damage, rows in id order).
#pragma once

#include "tear/math/types.h"

#include <cstddef>
#include <vector>

namespace tear {

struct CrackFigures {
  size_t cracked = 0;   // particles with damage > threshold
  double fraction = 0;  // cracked / all particles
  // Unit normal of the cracks (in 2D the crack line runs at `angle_degrees` from +x, in
  // (-90, 90]): the direction along which the cracked rest positions pile into the narrowest
  // stripes (see crack_normal). Zero when fewer than 3 particles are cracked.
  Vec3d normal = Vec3d::Zero();
  double angle_degrees = 0;  // 2D only
  // Median over the cracked particles of the width of the cracked band through them, measured
  // along the normal (see band_width), in scene units and in particle spacings.
  double width = 0;
  double width_spacings = 0;
};

// `rest` and `damage` per particle (same order); z = 0 in 2D. `spacing` is the particles'
// rest spacing (dx / ppc^(1/dim)).
CrackFigures measure_cracks(int dim, const std::vector<Vec3d>& rest,
                            const std::vector<double>& damage, double spacing,
                            double threshold = 0.5);

// The direction n along which the stripes {x : x . n in a bin} are most purely cracked: with
// the projections x . n of all points and of the `cracked` ones binned at about a spacing,
// the mean over the cracked points of the cracked share of their bin (1 when every crack is
// a straight band across the body along n's normal plane; about the cracked fraction in a
// wrong direction). Several parallel cracks count as well as one, and the body's shape does
// not bias it. 2D: angles every 0.25 degrees; 3D: 1200 directions over the half sphere, then
// refined around the best to 0.25 degrees.
Vec3d crack_normal(int dim, const std::vector<Vec3d>& points, const std::vector<char>& cracked,
                   double spacing);

// For each point, the extent along `normal` of the run of points through it inside a tube
// along the normal (2D: half-width `spacing`; 3D: radius `spacing`), counted as the points'
// volume (spacing^dim each) over the tube's cross-section; a gap of more than 2 spacings ends
// a run. The median over the points. A band of width w gives w (to sampling noise).
double band_width(int dim, const std::vector<Vec3d>& points, const Vec3d& normal,
                  double spacing);

// Symmetric mean distance between two point sets: the mean over both sets of each point's
// distance to the nearest point of the other set (0 for identical sets). Infinity when
// exactly one is empty.
double mean_nearest_distance(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b);

}  // namespace tear
