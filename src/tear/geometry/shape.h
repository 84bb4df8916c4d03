// geometry/: analytic shapes (signed distances, inside tests, normals, bounds, transforms), used
// to sample bodies and as colliders. Knows nothing of particles, grids or scenes.
// Geometry is always 3D double; 2D shapes use z = 0 and ignore the third axis.
#pragma once

#include "tear/geometry/mesh_solid.h"
#include "tear/math/types.h"

#include <Eigen/Geometry>

#include <memory>

namespace tear {

// Rigid transform plus uniform scale, applied as x_world = translate + R * (scale * x_local).
struct ShapeTransform {
  Vec3d translate = Vec3d::Zero();
  Eigen::Matrix3d rotate = Eigen::Matrix3d::Identity();
  double scale = 1.0;
  Vec3d to_local(const Vec3d& p) const { return rotate.transpose() * (p - translate) / scale; }
  Vec3d to_world(const Vec3d& p) const { return translate + rotate * (scale * p); }
};

struct Shape {
  enum class Type { Box, Sphere, Cylinder, Tube, HalfSpace, Mesh, Cone, Torus, Wedge };
  Type type = Type::Box;
  int dim = 3;
  // box
  Vec3d min = Vec3d::Zero(), max = Vec3d::Zero();
  // sphere (disk in 2D), cylinder, tube, cone, torus, wedge: centre; cylinder, tube, cone,
  // torus, wedge: unit axis; cylinder, tube, cone: height along it, centred on the centre.
  Vec3d center = Vec3d::Zero();
  Vec3d axis = Vec3d::UnitX();
  double radius = 0, inner_radius = 0, height = 0;
  // cone: radius and inner_radius at the bottom (-height/2 along the axis), these at the top
  // (+height/2), linear in between (inner radii 0: a solid cone or frustum).
  double radius_top = 0, inner_radius_top = 0;
  // torus: the tube's radius about the circle of `radius` around the axis.
  double tube_radius = 0;
  // wedge: the part of the ball (shell with inner_radius) between two half-planes through the
  // axis, `angle` radians apart, symmetric about `direction` (a unit vector normal to the axis).
  double angle = 0;
  Vec3d direction = Vec3d::UnitY();
  // half_space: a point on the plane and the outward normal of the solid side's boundary;
  // the solid occupies {x : (x - point) . normal <= 0}.
  Vec3d point = Vec3d::Zero(), normal = Vec3d::UnitY();
  // mesh (3D only): the closed surface, in the shape's local frame; shared by copies.
  std::shared_ptr<const MeshSolid> mesh;
  ShapeTransform transform;

  // Signed distance (negative inside), in world units. Exact for box/sphere/half_space/mesh,
  // exact up to the transform's uniform scale for the others.
  double sdf(const Vec3d& p) const;
  // Whether p is in the solid (sdf <= 0; for a mesh, its winding number test alone).
  bool inside(const Vec3d& p) const;
  // Outward unit normal (gradient of sdf) at p: finite differences, or a mesh's own normal.
  Vec3d normal_at(const Vec3d& p) const;
  // World-space axis-aligned bounds (half_space: infinite).
  void bounds(Vec3d* lo, Vec3d* hi) const;
  // World-space centre used for angular velocity of colliders.
  Vec3d world_center() const;
};

}  // namespace tear
