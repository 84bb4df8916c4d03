// grid/: colliders and domain walls acting on grid velocities: analytic shapes (geometry/)
// moving with a prescribed velocity, in sticky | slip | separate contact with Coulomb friction.
// Knows nothing of scenes: a Collider is plain settings that scene/ fills in.
#pragma once

#include "tear/geometry/shape.h"
#include "tear/grid/sparse_grid.h"

#include <vector>

namespace tear {

enum class ContactType { Sticky, Slip, Separate, None };

// An analytic collider: its shape at rest, its rigid motion and how it touches the material.
struct Collider {
  ContactType type = ContactType::Sticky;  // never None here
  Shape shape;
  double friction = 0;
  Vec3d velocity = Vec3d::Zero();
  Vec3d angular_velocity = Vec3d::Zero();  // about the shape's world centre
  double start = 0, end = 1e30;            // active for start <= time <= end
};

// Nodes closer than this many cells to a domain face are wall nodes.
constexpr int kWallNodes = 3;

// Velocity of a node after contact with a boundary moving at `v_wall`, outward unit normal
// `n` of the boundary (pointing into the material side): sticky takes the boundary velocity;
// slip removes the normal relative velocity; separate removes it only when approaching.
// Friction (Coulomb, coefficient mu) reduces the tangential relative velocity by mu |v_n|.
template <int Dim>
Vec<Dim> contact_velocity(const Vec<Dim>& v, const Vec<Dim>& v_wall, const Vec<Dim>& n,
                          ContactType type, Real friction);

// A collider at a given time: where it is and how fast it moves.
struct ColliderState {
  bool active = false;
  Vec3d displacement = Vec3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // about the shape's initial centre
  Vec3d center0 = Vec3d::Zero();
};

ColliderState collider_state(const Collider& c, double time);

// The collider's shape where `state` puts it: the rigid motion folded into the shape's
// transform, so that placed.sdf(p) is the rest shape's distance at the point that moves to p
// (for pictures: render/ draws shapes, not colliders).
Shape placed_shape(const Collider& c, const ColliderState& state);

// Apply domain walls and every active collider to the grid velocities at `time` (both fields
// of a node where the crack fields are split).
template <int Dim>
void apply_colliders(SparseGrid<Dim>& grid, ContactType walls,
                     const std::vector<Collider>& colliders, double time);

}  // namespace tear
