// grid/: boundary conditions on grid velocities: domain walls and analytic colliders
// (sticky | slip | separate, Coulomb friction), moving with a prescribed velocity.
#pragma once

#include "tear/grid/sparse_grid.h"
#include "tear/scene/scene.h"

#include <vector>

namespace tear {

// Nodes closer than this many cells to a domain face are wall nodes.
constexpr int kWallNodes = 3;

// Velocity of a node after contact with a boundary moving at `v_wall`, outward unit normal
// `n` of the boundary (pointing into the material side): sticky takes the boundary velocity;
// slip removes the normal relative velocity; separate removes it only when approaching.
// Friction (Coulomb, coefficient mu) reduces the tangential relative velocity by mu |v_n|.
template <int Dim>
Vec<Dim> contact_velocity(const Vec<Dim>& v, const Vec<Dim>& v_wall, const Vec<Dim>& n,
                          WallType type, Real friction);

// A boundary collider at a given time: where it is and how fast it moves.
struct ColliderState {
  bool active = false;
  Vec3d displacement = Vec3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // about the shape's initial centre
  Vec3d center0 = Vec3d::Zero();
};

ColliderState collider_state(const BoundarySpec& b, double time);

// Apply domain walls and every active collider to the grid velocities at `time`.
template <int Dim>
void apply_boundaries(SparseGrid<Dim>& grid, WallType walls,
                      const std::vector<BoundarySpec>& boundaries, double time);

}  // namespace tear
