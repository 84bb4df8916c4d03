// io/: the codimensional parts of a frame (cloth, yarn, hair): a mesh's vertices with their
// columns, its elements (triangles or segments) with theirs, written beside the particles'
// frame as DIR/frames/NNNNN.PART.EXT (ARCHITECTURE.md "Meshes in groups and frames").
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

struct MeshPart {
  std::string name;  // "curves", "surfaces" or "fem": the file's part name
  int corners = 3;   // 2: segments, 3: triangles, 4: tetrahedra (a volume: written as VTU only)
  PointTable vertices;  // id, x y z, vx vy vz, ... (row k is vertex k)
  std::vector<std::array<uint32_t, 4>> elements;  // vertex rows (the first `corners` of each)
  PointTable element_columns;  // one row per element: id, contact, ...
};

// The formats a mesh part can be written in (scene output.mesh_formats): "ply", "obj", "vtu",
// "geo".
const std::vector<std::string>& mesh_part_formats();
// The formats a run writes `part` in: `requested` (output.mesh_formats) for surfaces and curves;
// "vtu" alone for a volume (tetrahedra), whatever was requested.
std::vector<std::string> mesh_part_formats_of(const MeshPart& part,
                                              const std::vector<std::string>& requested);
// The part encoded in `format` (one of mesh_part_formats(); a volume only in "vtu").
std::string encode_mesh_part(const MeshPart& part, const std::string& format);
// DIR/frames/NNNNN.PART.EXT.
std::string mesh_part_path(const std::string& dir, int frame, const std::string& part,
                           const std::string& format);
// Binary little-endian PLY: element vertex (the vertex columns), then element face (list uchar
// int vertex_indices, then the element columns) for triangles or element edge (int vertex1,
// int vertex2, then the element columns) for segments.
std::string encode_mesh_part_ply(const MeshPart& part);
// Wavefront OBJ: "v x y z" per vertex, then "f a b c" per triangle or "l a b" per segment
// (1-based); OBJ has no place for the other columns.
std::string encode_mesh_part_obj(const MeshPart& part);
// VTK XML unstructured grid (ascii): the vertices as Points with their other columns as
// PointData (vx vy vz as "velocity"), tetrahedra (VTK_TETRA), triangles (VTK_TRIANGLE) or
// segments (VTK_LINE) as cells with the element columns as CellData (fx fy fz as "fiber").
std::string encode_mesh_part_vtu(const MeshPart& part);
// Houdini's classic ASCII geometry (.geo; the layout of sidefx.com/docs/houdini/io/formats/geo
// and of VTK's vtkHoudiniPolyDataWriter): "PGEOMETRY V5", the counts, the point attributes
// (vx vy vz as the vector "v", the other vertex columns by name; int or float), each point as
// "x y z 1 (values)", the element columns as primitive attributes, then "Run N Poly" and one
// polygon per element, "3 < a b c [values]" (closed) for triangles and "2 : a b [values]"
// (open) for segments (0-based point numbers), and "beginExtra" / "endExtra".
std::string encode_mesh_part_geo(const MeshPart& part);
// DIR/PART.pvd: a ParaView collection of DIR/frames/NNNNN.PART.vtu at the given frame times.
void write_mesh_part_pvd(const std::string& dir, const std::string& part,
                         const std::map<int, double>& times);

// The inverse, for tests and tools: the vertex and element tables and the connectivity (name
// unset). Throws std::runtime_error ("bad PLY mesh part: ...") on a malformed file or an element
// index out of range.
MeshPart decode_mesh_part_ply(const std::string& bytes);

// The part names a run writes and reads back: "curves", "surfaces" (codimensional bodies), "fem"
// (the surfaces of FEM bodies: driver/fem_simulation.cpp). FEM runs in 3D also write the part
// "volume" (their tetrahedra, VTU only), which is not read back.
const std::vector<std::string>& mesh_part_names();
// The codimensional parts of frame `frame` of the run folder `dir`, read from their PLY files
// (DIR/frames/NNNNN.PART.ply, the default output.mesh_formats); none where the frame has none.
// Throws std::runtime_error naming the file when a part was written only in other formats
// (OBJ keeps no columns; VTU is not read back) or does not decode.
std::vector<MeshPart> read_mesh_parts(const std::string& dir, int frame);

}  // namespace tear
