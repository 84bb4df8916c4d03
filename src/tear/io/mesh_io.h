// io/: triangle meshes on disk: OBJ and PLY with a face element, as `tear mesh` writes them,
// and STL; read for mesh objects (scene "mesh" shapes).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tear {

struct TriMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<int32_t, 3>> triangles;  // counter-clockwise seen from outside
  // Polyline segments (OBJ "l" statements, split into consecutive pairs; a PLY "edge" element):
  // the curves of codimensional bodies.
  std::vector<std::array<int32_t, 2>> segments;
};

// Wavefront OBJ ("v x y z" and "f i j k", 1-based), text. Coordinates are written in the
// shortest form that reads back to the same float.
std::string encode_obj(const TriMesh& mesh);
// Binary little-endian PLY: element vertex (float x y z), element face (list uchar int
// vertex_indices).
std::string encode_mesh_ply(const TriMesh& mesh);
// Read what encode_obj / encode_mesh_ply write, and more: OBJ with "i/t/n" and negative
// indices (other statements ignored), PLY in ascii or binary_little_endian with any scalar
// types and extra properties. Polygons are split into triangle fans, polylines (OBJ "l i j k",
// a PLY "edge" element with vertex1 and vertex2) into segments. A PLY needs a face or an edge
// element. Throw std::runtime_error with the reason (and the line, face or edge) on malformed
// input.
TriMesh decode_obj(const std::string& text);
TriMesh decode_mesh_ply(const std::string& bytes);
// Binary STL (80-byte header, triangle count, 50 bytes a triangle); each triangle gets three
// vertices of its own, as in the format.
std::string encode_stl(const TriMesh& mesh);
// Binary or ascii STL ("solid ... facet ... outer loop vertex x y z ... endsolid"): three
// vertices per triangle, none shared (MeshSolid merges equal ones); facet normals ignored.
TriMesh decode_stl(const std::string& bytes);
// A mesh file by its extension (.obj, .ply or .stl, any case): read_file, then the decoder.
// Errors name the file.
TriMesh read_mesh_file(const std::string& path);

}  // namespace tear
