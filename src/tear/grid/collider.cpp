#include "tear/grid/collider.h"

#include <Eigen/Geometry>
#include "tear/exec/parallel.h"

#include <cmath>
#include <limits>
#include <utility>

namespace tear {

template <int Dim>
Vec<Dim> contact_velocity(const Vec<Dim>& v, const Vec<Dim>& v_wall, const Vec<Dim>& n,
                          ContactType type, Real friction) {
  if (type == ContactType::Sticky) return v_wall;
  if (type == ContactType::None) return v;
  Vec<Dim> rel = v - v_wall;
  const Real vn = rel.dot(n);
  if (type == ContactType::Separate && vn >= 0) return v;  // leaving the boundary: free
  Vec<Dim> vt = rel - vn * n;
  if (friction > 0 && vn < 0) {
    const Real t = vt.norm();
    vt = t > -friction * vn ? Vec<Dim>(vt * (1 + friction * vn / t)) : Vec<Dim>::Zero();
  }
  return v_wall + vt;
}

ColliderState collider_state(const Collider& c, double time) {
  ColliderState s;
  s.center0 = c.shape.world_center();
  if (time < c.start || time > c.end) return s;
  s.active = true;
  const double elapsed = time - c.start;
  s.displacement = c.velocity * elapsed;
  const double w = c.angular_velocity.norm();
  if (w > 0) s.rotation = Eigen::AngleAxisd(w * elapsed, c.angular_velocity / w).toRotationMatrix();
  return s;
}

Shape placed_shape(const Collider& c, const ColliderState& s) {
  // x -> centre0 + displacement + R (x - centre0) after x_world = t + Q (scale x_local).
  Shape placed = c.shape;
  ShapeTransform& t = placed.transform;
  t.translate = s.center0 + s.displacement + s.rotation * (t.translate - s.center0);
  t.rotate = s.rotation * t.rotate;
  return placed;
}

ColliderContacts::ColliderContacts(const std::vector<Collider>& colliders, double time)
    : colliders_(colliders) {
  for (const Collider& col : colliders) states_.push_back(collider_state(col, time));
  // World boxes around the moved colliders: points outside skip the signed distance (the boxes
  // are a little larger than the shapes, so no point inside is skipped; half-spaces: no box).
  for (size_t c = 0; c < colliders.size(); ++c) {
    Vec3d lo = Vec3d::Constant(-std::numeric_limits<double>::infinity()), hi = -lo;
    if (colliders[c].shape.type != Shape::Type::HalfSpace) {
      Vec3d rest_lo, rest_hi;
      colliders[c].shape.bounds(&rest_lo, &rest_hi);
      const ColliderState& st = states_[c];
      std::swap(lo, hi);
      for (int k = 0; k < 8; ++k) {
        const Vec3d corner((k & 1) ? rest_hi.x() : rest_lo.x(), (k & 2) ? rest_hi.y() : rest_lo.y(),
                           (k & 4) ? rest_hi.z() : rest_lo.z());
        const Vec3d w = st.center0 + st.displacement + st.rotation * (corner - st.center0);
        lo = lo.cwiseMin(w), hi = hi.cwiseMax(w);
      }
      const double pad = 1e-9 * (1 + (hi - lo).cwiseAbs().maxCoeff());
      lo.array() -= pad, hi.array() += pad;
    }
    boxes_.emplace_back(lo, hi);
  }
}

template <int Dim>
NodeContacts<Dim>::NodeContacts(const SparseGrid<Dim>& grid, ContactType walls,
                                const std::vector<Collider>& colliders, double time)
    : grid_(grid), walls_(walls), colliders_(colliders, time), n_nodes_(grid.num_nodes()) {}

template <int Dim>
void apply_colliders(SparseGrid<Dim>& grid, ContactType walls,
                     const std::vector<Collider>& colliders, double time) {
  const NodeContacts<Dim> contacts(grid, walls, colliders, time);
  auto contact = [&](int node, Vec<Dim>& v) {
    contacts.visit(node, [&](const Vec<Dim>& n, const Vec<Dim>& v_wall, ContactType type,
                             Real friction) {
      v = contact_velocity<Dim>(v, v_wall, n, type, friction);
    });
  };
  // Both velocity fields of a node where crack fields are split (SparseGrid::mass2).
  const bool split = grid.split();
  parallel_for(size_t(grid.num_blocks()), [&](size_t blk_index) {
    const int blk = int(blk_index);
    for (int l = 0; l < SparseGrid<Dim>::kNodesPerBlock; ++l) {
      const int node = blk * SparseGrid<Dim>::kNodesPerBlock + l;
      if (grid.mass[node] > 0) contact(node, grid.velocity[node]);
      if (split && grid.mass2[node] > 0) contact(node, grid.velocity2[node]);
    }
  });
}

template class NodeContacts<2>;
template class NodeContacts<3>;
template Vec<2> contact_velocity<2>(const Vec<2>&, const Vec<2>&, const Vec<2>&, ContactType, Real);
template Vec<3> contact_velocity<3>(const Vec<3>&, const Vec<3>&, const Vec<3>&, ContactType, Real);
template void apply_colliders<2>(SparseGrid<2>&, ContactType, const std::vector<Collider>&, double);
template void apply_colliders<3>(SparseGrid<3>&, ContactType, const std::vector<Collider>&, double);

}  // namespace tear
