// render/: the colliders of a picture: shapes (geometry/) placed where they are at the frame's
// time, found along each camera ray and composited, translucent with a dark outline, over what
// the ray sees behind them. Knows shapes and cameras; nothing of colliders' motion or scenes.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "tear/geometry/shape.h"
#include "tear/render/camera.h"

namespace tear {

// How much of a surface point at `p` shows against the background: 1 near the body, fading
// with the horizontal distance (across `up`) from `center` over a few times `size`. The ground
// and the colliders of 3D pictures fade alike, so an endless plane meets the horizon softly.
double distance_fade(const Eigen::Vector3d& p, const Eigen::Vector3d& center,
                     const Eigen::Vector3d& up, double size);

// In 3D each shape is sphere traced by its signed distance, lit by the key light without
// shadows, and the body in front of it hides it; rays that pass within about a pixel of a
// shape draw its silhouette. In 2D the shapes lie in the z = 0 plane and are drawn over the
// particles (in a plane nothing is in front): filled where the plane point is inside, outlined
// where it is within about a pixel of the boundary, so a grip shows where it holds the body.
class ColliderLayer {
 public:
  // `up` (unit) and `ground`: the picture's ground plane; a half space facing up whose plane is
  // at or below it is the ground itself (or hidden under it) and is not drawn. `key` (unit):
  // towards the key light. `center`, `size`: the stage's (distance_fade, the reach of rays).
  ColliderLayer(const std::vector<Shape>& shapes, int dim, const CameraView& view,
                const Eigen::Vector3d& up, double ground, const Eigen::Vector3d& key,
                const Eigen::Vector3d& center, double size);

  bool empty() const { return shapes_.empty(); }

  // The colour of a camera sample along unit direction `d` that sees `behind` (linear RGB) at
  // distance `t_behind` (infinite: the background), with the colliders in front of it
  // composited over it, the farthest first.
  Eigen::Vector3f over(const Eigen::Vector3d& d, double t_behind,
                       const Eigen::Vector3f& behind) const;

 private:
  struct Placed {
    const Shape* shape;
    Eigen::Vector3d lo, hi;  // padded world bounds (infinite for a half space)
  };
  // What one shape puts on a ray: a translucent surface or an outline at distance t.
  struct Layer {
    double t;
    Eigen::Vector3f color;
    float alpha;
  };
  bool find_2d(const Placed& s, const Eigen::Vector3d& d, double t_behind, Layer* out) const;
  bool find_3d(const Placed& s, const Eigen::Vector3d& d, double t_behind, Layer* out) const;

  std::vector<Placed> shapes_;
  int dim_;
  Eigen::Vector3d eye_, up_, key_, center_;
  double size_, pixel_;          // pixel_: a pixel's width per unit distance from the eye
  Eigen::Vector3f fill_, edge_;  // linear
};

}  // namespace tear
