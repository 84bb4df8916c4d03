// geometry/: a solid bounded by a closed triangle mesh, for mesh objects (SCENE_FORMAT.md
// "mesh" shapes): the inside test, the distance to the surface, the volume.
//
// Inside is decided by the generalised winding number w(p) = sum of the triangles' signed solid
// angles / 4 pi (Jacobson et al. 2013): 1 inside a closed, outward-oriented surface, 0 outside,
// with no special cases for points whose rays would graze an edge or a vertex. It is evaluated
// exactly and fast over a bounding-volume hierarchy: a subtree whose box does not contain p
// contributes what a fan over its boundary loop contributes (the subtree and the fan together
// bound a region whose hull lies in the box, which winds zero times around p), so far away
// only a few fan triangles are summed instead of every triangle. A voxel grid over the mesh
// answers most inside tests at once: voxels that no triangle's box touches form connected
// regions that the surface does not cross, so one winding number per region decides all of
// their points; only points in voxels near the surface are evaluated one by one.
#pragma once

#include "tear/math/types.h"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tear {

class MeshSolid {
 public:
  // Vertices with the same coordinates are merged first (OBJ seams, STL's triangle soup). The
  // mesh must then be a closed, consistently oriented 2-manifold enclosing a non-zero volume:
  // otherwise std::runtime_error says what is wrong and where (triangle and vertex numbers,
  // 0-based). An inward-oriented mesh (negative volume) is turned inside out.
  // `name` (the file, say) starts the message of inside()'s error.
  MeshSolid(const std::vector<Vec3d>& vertices, const std::vector<std::array<int, 3>>& triangles,
            std::string name = "the mesh");

  // The generalised winding number at p: 1 inside, 0 outside (on the surface itself, a value
  // in between).
  double winding_number(const Vec3d& p) const;
  // Whether p is inside: on the surface, or a winding number >= 1/2. Throws where the winding
  // number is 1.5 or more, or -0.5 or less: the surface crosses itself or has overlapping
  // shells there.
  bool inside(const Vec3d& p) const;
  // Distance from p to the surface, and the same signed (negative inside).
  double distance(const Vec3d& p) const;
  double signed_distance(const Vec3d& p) const { return inside(p) ? -distance(p) : distance(p); }
  // Outward unit normal of the signed distance at p: towards p from its nearest surface point
  // (away from it inside); on the surface, the nearest triangle's normal.
  Vec3d normal(const Vec3d& p) const;

  const Vec3d& lo() const { return nodes_[0].lo; }
  const Vec3d& hi() const { return nodes_[0].hi; }
  double volume() const { return volume_; }
  size_t num_triangles() const { return triangles_.size(); }
  size_t num_vertices() const { return vertices_.size(); }
  bool turned_inside_out() const { return turned_; }
  // The merged vertices and the outward-oriented triangles (in BVH order).
  const std::vector<Vec3d>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

 private:
  using Tri = std::array<int, 3>;
  struct Node {
    Vec3d lo, hi;
    int begin = 0, end = 0;          // triangles_[begin, end) (sorted by subtree)
    int left = -1, right = -1;       // children (-1: a leaf)
    int cap_begin = 0, cap_end = -1;  // caps_[cap_begin, cap_end): the boundary fan; none if end < begin
  };
  int build(int begin, int end);
  void classify_voxels();
  void make_cap(Node* node);
  double solid_angle(const Tri& t, const Vec3d& p, bool* on_surface) const;
  double winding(const Vec3d& p, bool* on_surface) const;
  // Distance to the surface, with the nearest point and its triangle.
  double closest(const Vec3d& p, Vec3d* nearest, int* triangle) const;

  std::vector<Vec3d> vertices_;
  std::vector<Tri> triangles_;
  std::vector<Tri> caps_;
  std::vector<Node> nodes_;
  // The voxel grid: cubes of side voxel_h_ from voxel_lo_, voxel_n_ per axis (x fastest), one
  // layer beyond the mesh's bounds; state kOut, kIn, or kExact (near the surface, or in a
  // region whose winding number is not 0 or 1: evaluated per point).
  enum : uint8_t { kOut = 0, kIn = 1, kExact = 2 };
  Vec3d voxel_lo_;
  double voxel_h_ = 0;
  std::array<int, 3> voxel_n_{};
  std::vector<uint8_t> voxels_;
  double volume_ = 0;
  bool turned_ = false;
  std::string name_;
};

}  // namespace tear
