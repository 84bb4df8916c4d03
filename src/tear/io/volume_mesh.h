// io/: volume meshes in files: tetrahedra (3D) or triangles (2D) with per-node and per-cell
// columns, read from gmsh MSH 4.1, TetGen/Triangle .node + .ele and VTK XML unstructured grids,
// written as VTU. A neutral type: fem/ makes its FemMesh of one and its frames into one; io/
// knows nothing of FEM. Readers check counts and index ranges, never geometry (inverted or
// degenerate elements are fem's check_fem_mesh's business).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

struct VolumeMesh {
  int dim = 3;                                 // 3: tetrahedra, 2: triangles
  std::vector<std::array<double, 3>> nodes;    // z = 0 in 2D
  std::vector<std::array<uint32_t, 4>> cells;  // 0-based node indices; the 4th 0 for triangles
  // For writing (and what decode_volume_vtu reads back): one row per node (e.g. vx vy vz) and
  // one per cell (e.g. energy, fx fy fz); no columns x, y, z (the nodes are the positions).
  PointTable node_columns, cell_columns;
};

// Corners per cell: 4 in 3D, 3 in 2D.
inline int corners(const VolumeMesh& m) { return m.dim == 3 ? 4 : 3; }

// Throws std::runtime_error with the reason unless `m` is a mesh the readers could return: dim
// 2 or 3, at least one cell, every corner a node, z = 0 in 2D, column
// tables of one row per node and per cell (or without columns), no node column x, y or z.
// The message begins with `context` ("gmsh: ").
void check_volume_mesh(const VolumeMesh& m, const std::string& context = "");

// gmsh MSH 4.1, ASCII or binary (data-size 8, either byte order): $Nodes (sparse tags become
// 0-based indices in file order) and $Elements: 4-node tetrahedra (type 4), or 3-node triangles
// (type 2) where there are no tetrahedra. Elements of lower dimension (points, lines, the
// surface triangles of a tet mesh) are skipped; other elements of the mesh's dimension and
// every higher-order element (10-node tetrahedra, 6-node triangles, ...) are refused by name;
// other sections are skipped. MSH 2.x and 4.0 are refused. Throws std::runtime_error
// ("gmsh: line 17: ..." or "gmsh: byte 120: ...").
VolumeMesh decode_gmsh(const std::string& bytes);

// TetGen's .node and .ele (and Triangle's: 2D nodes, 3-corner elements): '#' comments, a count
// line, then one line per node "index x y [z] [attributes] [marker]" and per element
// "index n1 .. nk [attributes]"; the index base (0 or 1) is the first node's index and nodes
// must be numbered consecutively. 4 corners: tetrahedra; 3: triangles; second order (10 or 6)
// is refused. Attributes and markers are skipped. Errors name the file ("tetgen .node",
// "tetgen .ele", or the given names) and the line.
VolumeMesh decode_tetgen(const std::string& node_text, const std::string& ele_text);
VolumeMesh decode_tetgen(const std::string& node_text, const std::string& ele_text,
                         const std::string& node_name, const std::string& ele_name);

// A VTK XML unstructured grid (one Piece, ascii or inline binary, uncompressed) of VTK_TETRA
// (10) or, where it has no 3D cell, VTK_TRIANGLE (5) cells; cells of lower dimension (vertices,
// lines, the triangles of a tet mesh) are skipped, other cells of the mesh's dimension
// (VTK_QUADRATIC_TETRA, VTK_HEXAHEDRON, ...) refused by name. Point arrays become node columns
// and cell arrays (of the kept cells) cell columns, named as io/point_groups.h says ("velocity"
// -> vx vy vz, "fiber" -> fx fy fz). Throws std::runtime_error("bad VTU: ...").
VolumeMesh decode_volume_vtu(const std::string& bytes);

// Binary VTU (base64, UInt64 headers) of one Piece: Points (Float64), cells VTK_TETRA or
// VTK_TRIANGLE, node columns as PointData and cell columns as CellData (vx vy vz as "velocity",
// fx fy fz as "fiber", every other column as an array of its own name; Int32 for integer
// columns, Float64 for Float64 ones, Float32 otherwise). decode_volume_vtu reads it back.
std::string encode_volume_vtu(const VolumeMesh& m);

// The mesh in `path`, by extension: .msh (gmsh), .node or .ele (TetGen: X.node and X.ele are
// read together, whichever is given), .vtu. Errors begin with the path: "PATH: gmsh: line 17:
// ...", "X.ele: line 5: ...".
VolumeMesh read_volume_mesh(const std::string& path);

}  // namespace tear
