// fem/: what tear hands the tetrahedral and triangle mesher and gets back. The mesher is netgen's
// nglib (LGPL-2.1, Debian's libnglib-dev), linked into a module of its own,
// libtear_netgen.so (fem/netgen/mesher.cpp), loaded the first time a mesh is made
// (netgen_module()): nglib pulls in Open MPI, Python and Open CASCADE when it is loaded, which
// runs without an FEM body do not need. Plain data crosses, no netgen type.
//
// Why netgen (docs/fem.md "Meshing"): of the tet meshers Debian has, only netgen's licence
// (LGPL) leaves tear free to take a permissive licence; TetGen is AGPL, gmsh GPL with an
// exception, CGAL's Mesh_3 GPL.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace tear {

// 2D: one boundary segment of the region to mesh, its inside on the left: a straight line a-b,
// or (arc) netgen's rational quadratic from a to b with control point c, which is a circular arc
// where c is the corner of the tangents at a and b (quarter circles here).
struct BoundarySegment2 {
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero(),
                  c = Eigen::Vector2d::Zero();
  bool arc = false;
};

struct MeshRequest {
  int dim = 3;
  double max_h = 0;  // target (largest) edge length
  // 3D: a closed, outward-oriented triangle surface. netgen remeshes it at max_h (its edges
  // where faces meet at more than 30 degrees are kept), then fills it with tetrahedra.
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  // 2D: the region's boundary, outer loops counter-clockwise and holes clockwise.
  std::vector<BoundarySegment2> segments;
};

struct MeshResult {
  std::vector<Eigen::Vector3d> nodes;          // z = 0 in 2D
  std::vector<std::array<int, 4>> elements;    // 0-based; triangles leave the 4th at -1
  std::string error;                           // empty: meshed
};

// The module's functions; `abi` is the kNetgenAbi it was built with (first member: see
// exec/plugin.h).
struct NetgenModule {
  int abi;
  MeshResult (*mesh)(const MeshRequest&);
  const char* (*version)();
};

// Changed with the structs above, so that a module of another build is refused.
constexpr int kNetgenAbi = 1;
#define TEAR_NETGEN_ENTRY "tear_netgen_module"
#define TEAR_NETGEN_FILE "libtear_netgen.so"

// The module, loaded once (exec/plugin.h says from where); throws std::runtime_error naming
// each file tried and why it failed.
const NetgenModule& netgen_module();

}  // namespace tear
