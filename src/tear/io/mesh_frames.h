// io/: the codimensional parts of a frame (cloth, yarn, hair): a mesh's vertices with their
// columns, its elements (triangles or segments) with theirs, written beside the particles'
// frame as DIR/frames/NNNNN.PART.EXT (ARCHITECTURE.md "Meshes in groups and frames").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

struct MeshPart {
  std::string name;  // "curves" or "surfaces": the file's part name
  int corners = 3;   // 2: segments, 3: triangles
  PointTable vertices;  // id, x y z, vx vy vz, ... (row k is vertex k)
  std::vector<std::array<uint32_t, 3>> elements;  // vertex rows (segments use the first two)
  PointTable element_columns;  // one row per element: id, contact, ...
};

// The formats a mesh part is written in (a subset of the scene's output.formats): "ply".
bool is_mesh_part_format(const std::string& format);
// DIR/frames/NNNNN.PART.EXT.
std::string mesh_part_path(const std::string& dir, int frame, const std::string& part,
                           const std::string& format);
// Binary little-endian PLY: element vertex (the vertex columns), then element face (list uchar
// int vertex_indices, then the element columns) for triangles or element edge (int vertex1,
// int vertex2, then the element columns) for segments.
std::string encode_mesh_part_ply(const MeshPart& part);
// The inverse, for tests and tools: the vertex and element tables and the connectivity.
MeshPart decode_mesh_part_ply(const std::string& bytes);

}  // namespace tear
