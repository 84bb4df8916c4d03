// grid/: colliders and domain walls acting on grid velocities: analytic shapes (geometry/)
// moving with a prescribed velocity, in sticky | slip | separate contact with Coulomb friction.
// Knows nothing of scenes: a Collider is plain settings that scene/ fills in.
#pragma once

#include "tear/geometry/shape.h"
#include "tear/grid/sparse_grid.h"

#include <Eigen/Geometry>
#include <utility>
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

// The active colliders at one time, tested at any point (a grid node, an FEM node).
class ColliderContacts {
 public:
  ColliderContacts(const std::vector<Collider>& colliders, double time);

  // fn(n, v_wall, type, friction) for each active collider whose moved shape holds p, in scene
  // order: n the collider's unit normal pointing into the material side, v_wall its velocity at p.
  template <int Dim, class Fn>
  void visit(const Vec3d& p, Fn&& fn) const;
  bool empty() const { return states_.empty(); }

 private:
  const std::vector<Collider>& colliders_;
  std::vector<ColliderState> states_;
  std::vector<std::pair<Vec3d, Vec3d>> boxes_;  // world boxes around the moved colliders
};

template <int Dim, class Fn>
void ColliderContacts::visit(const Vec3d& p, Fn&& fn) const {
  for (size_t c = 0; c < colliders_.size(); ++c) {
    const ColliderState& s = states_[c];
    if (!s.active) continue;
    if ((p.array() < boxes_[c].first.array()).any() || (p.array() > boxes_[c].second.array()).any())
      continue;
    const Collider& col = colliders_[c];
    const Vec3d centre = s.center0 + s.displacement;
    const Vec3d q = s.center0 + s.rotation.transpose() * (p - centre);
    if (!col.shape.inside(q)) continue;
    const Vec3d n3 = s.rotation * col.shape.normal_at(q);
    const Vec3d vw3 = col.velocity + col.angular_velocity.cross(p - centre);
    fn(Vec<Dim>(n3.template head<Dim>().template cast<Real>().normalized()),
       Vec<Dim>(vw3.template head<Dim>().template cast<Real>()), col.type, Real(col.friction));
  }
}

// The boundaries touching grid nodes at one time: the domain walls (nodes within kWallNodes of a
// face) and every active collider whose moved shape holds the node. apply_colliders and an
// implicit solve's velocity constraints share it.
template <int Dim>
class NodeContacts {
 public:
  NodeContacts(const SparseGrid<Dim>& grid, ContactType walls,
               const std::vector<Collider>& colliders, double time);

  // fn(n, v_wall, type, friction) for each boundary touching `node`, walls (one call per face
  // the node is near) then colliders in scene order: n the boundary's unit normal pointing into
  // the material side, v_wall its velocity at the node.
  template <class Fn>
  void visit(int node, Fn&& fn) const;

 private:
  const SparseGrid<Dim>& grid_;
  ContactType walls_;
  ColliderContacts colliders_;
  IVec<Dim> n_nodes_;
};

template <int Dim>
template <class Fn>
void NodeContacts<Dim>::visit(int node, Fn&& fn) const {
  if (walls_ != ContactType::None) {
    const IVec<Dim> g = grid_.node_coord(node);
    for (int d = 0; d < Dim; ++d) {
      Vec<Dim> n = Vec<Dim>::Zero();
      if (g[d] < kWallNodes)
        n[d] = 1;
      else if (g[d] > n_nodes_[d] - 1 - kWallNodes)
        n[d] = -1;
      else
        continue;
      fn(n, Vec<Dim>::Zero().eval(), walls_, Real(0));
    }
  }
  if (colliders_.empty()) return;
  Vec3d p = Vec3d::Zero();
  p.template head<Dim>() = grid_.node_position(node).template cast<double>();
  colliders_.visit<Dim>(p, fn);
}

// I minus the projector onto the directions of a velocity v that the boundaries `visit` calls
// back with (visit(fn) as NodeContacts::visit(node, fn)) hold: all for a sticky one, the normal
// for slip, and for separate the normal unless v leaves it. What an implicit solve or a velocity
// projection may change there.
template <int Dim, class Visit>
Mat<Dim> free_directions_at(Visit&& visit, const Vec<Dim>& v) {
  Mat<Dim> fixed = Mat<Dim>::Zero();  // sum of e e^T over the fixed directions
  visit([&](const Vec<Dim>& n, const Vec<Dim>& v_wall, ContactType type, Real) {
    if (type == ContactType::Sticky) {
      fixed.setIdentity();
      return;
    }
    if (type == ContactType::None) return;
    if (type == ContactType::Separate && (v - v_wall).dot(n) > 0) return;  // leaving
    Vec<Dim> e = n - fixed * n;  // Gram-Schmidt against the directions fixed already
    if (e.norm() < Real(1e-6)) return;
    e.normalize();
    fixed += e * e.transpose();
  });
  return Mat<Dim>::Identity() - fixed;
}

// The same for a grid node.
template <int Dim>
Mat<Dim> free_directions(const NodeContacts<Dim>& contacts, int node, const Vec<Dim>& v) {
  return free_directions_at<Dim>([&](auto&& fn) { contacts.visit(node, fn); }, v);
}

// Apply domain walls and every active collider to the grid velocities at `time` (both fields
// of a node where the crack fields are split).
template <int Dim>
void apply_colliders(SparseGrid<Dim>& grid, ContactType walls,
                     const std::vector<Collider>& colliders, double time);

}  // namespace tear
