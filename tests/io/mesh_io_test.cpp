// OBJ and PLY triangle meshes: exact round trips, the header tear writes, what else is read,
// and the errors on malformed files.
#include "tear/io/mesh_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <utility>
#include <limits>
#include <string>

#include "io_fixture.h"
#include "tear/io/atomic_file.h"

namespace tear {
namespace {

// Floats that a careless printer would not read back exactly.
TriMesh awkward_mesh() {
  TriMesh m;
  m.vertices = {{0.1f, -0.2f, 1.0f / 3.0f},
                {1e-7f, -3.4e38f, std::numeric_limits<float>::denorm_min()},
                {123456.789f, 0.0f, -0.0f},
                {2.5f, 7.0f, -1e-30f}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 1}};
  return m;
}

void expect_same(const TriMesh& a, const TriMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (size_t i = 0; i < a.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k)  // bit for bit
      EXPECT_EQ(std::memcmp(&a.vertices[i][k], &b.vertices[i][k], sizeof(float)), 0)
          << "vertex " << i << " axis " << k << ": " << a.vertices[i][k] << " vs "
          << b.vertices[i][k];
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(MeshIo, ObjRoundTripIsExact) {
  const TriMesh m = awkward_mesh();
  const std::string text = encode_obj(m);
  expect_same(decode_obj(text), m);
  EXPECT_NE(text.find("\nv 0.1 -0.2 0.33333334\n"), std::string::npos) << text;  // shortest
  EXPECT_NE(text.find("\nf 1 2 3\n"), std::string::npos) << text;                // 1-based
  EXPECT_EQ(encode_obj(decode_obj(text)), text);
}

TEST(MeshIo, PlyRoundTripIsExactAndTheHeaderIsTheDocumentedOne) {
  const TriMesh m = awkward_mesh();
  const std::string bytes = encode_mesh_ply(m);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\nelement face 3\n"
      "property list uchar int vertex_indices\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  EXPECT_EQ(bytes.size(), header.size() + 4 * 12 + 3 * 13);
  expect_same(decode_mesh_ply(bytes), m);
}

TEST(MeshIo, EmptyMeshesRoundTrip) {
  EXPECT_TRUE(decode_obj(encode_obj(TriMesh{})).vertices.empty());
  const TriMesh back = decode_mesh_ply(encode_mesh_ply(TriMesh{}));
  EXPECT_TRUE(back.vertices.empty());
  EXPECT_TRUE(back.triangles.empty());
}

TEST(MeshIo, ReadsObjWithSlashesNegativeIndicesAndPolygons) {
  const TriMesh m = decode_obj(
      "# a quad and a triangle\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "vn 0 0 1\nvt 0 0\ns off\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\n");
  ASSERT_EQ(m.vertices.size(), 4u);
  using Tri = std::array<int32_t, 3>;
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 2, 3}}));
}

TEST(MeshIo, ReadsAsciiPlyWithOtherPropertiesAndElements) {
  const TriMesh m = decode_mesh_ply(
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nproperty uchar red\nelement face 2\n"
      "property list uchar uint vertex_indices\nproperty int flags\nelement edge 1\n"
      "property int a\nproperty int b\nend_header\n"
      "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n4 0 1 2 3 7\n3 3 2 1 0\n0 1\n");
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2], Eigen::Vector3f(1, 1, 0));
  using Tri = std::array<int32_t, 3>;
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
}

TEST(MeshIo, ObjErrorsNameTheLineAndTheReason) {
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nv 1 0\n"),
            "bad OBJ: line 2: vertex needs three numbers ('v 1 0')");
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nv 1 0 x\n"),
            "bad OBJ: line 2: vertex needs three numbers ('v 1 0 x')");
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nf 1 2 3\n"),
            "bad OBJ: line 2: vertex index 2 out of range (1 vertices so far)");
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nf 1 1\n"), "bad OBJ: line 2: face with 2 corners");
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nf 1 a 1\n"),
            "bad OBJ: line 2: face corner 'a' is not a vertex index");
  EXPECT_EQ(error_of(decode_obj, "v 0 0 0\nf 0 1 1\n"),
            "bad OBJ: line 2: vertex index 0 out of range (1 vertices so far)");
  EXPECT_EQ(error_of(decode_obj, "vertex 0 0 0\n"), "bad OBJ: line 1: unknown statement 'vertex'");
}

TEST(MeshIo, PlyErrorsNameTheReason) {
  const std::string good = encode_mesh_ply(awkward_mesh());
  EXPECT_EQ(error_of(decode_mesh_ply, "obj\n"), "bad PLY mesh: does not start with 'ply'");
  EXPECT_EQ(error_of(decode_mesh_ply, good.substr(0, good.size() - 1)),
            "bad PLY mesh: truncated data at face 2, property 'vertex_indices'");
  EXPECT_EQ(error_of(decode_mesh_ply, good.substr(0, 60)), "bad PLY mesh: no end_header line");
  EXPECT_EQ(error_of(decode_mesh_ply,
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n0 0 0\n"),
            "bad PLY mesh: no face element (nor an edge element)");
  EXPECT_EQ(error_of(decode_mesh_ply,
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                     "property float y\nelement face 0\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0\n"),
            "bad PLY mesh: vertex element has no scalar property 'z'");
  EXPECT_EQ(error_of(decode_mesh_ply,
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                     "property float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 1\n"),
            "bad PLY mesh: face 0, property 'vertex_indices': vertex index 1, expected an "
            "integer in [0, 1)");
  EXPECT_EQ(error_of(decode_mesh_ply,
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                     "property float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n"),
            "bad PLY mesh: face 0 has 2 corners");
  EXPECT_EQ(error_of(decode_mesh_ply, "ply\nformat binary_big_endian 1.0\nend_header\n"),
            "bad PLY mesh: unsupported format 'binary_big_endian' (binary_little_endian and "
            "ascii are read)");
  // A corrupt count cannot make the reader allocate terabytes.
  EXPECT_EQ(error_of(decode_mesh_ply,
                     "ply\nformat binary_little_endian 1.0\nelement vertex 999999999999\n"
                     "property float x\nproperty float y\nproperty float z\nelement face 0\n"
                     "property list uchar int vertex_indices\nend_header\n"),
            "bad PLY mesh: truncated: element 'vertex' has 999999999999 rows, found 0 bytes of "
            "data");
}

// Found by fuzzing (tests/fuzz): the rows of an element without properties were stepped through
// one by one, so a declared count of 10^18 hung the reader. They hold nothing and are skipped.
TEST(MeshIo, PlyRowsWithoutPropertiesAreSkippedHoweverMany) {
  const TriMesh m = decode_mesh_ply(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement marker 999999999999999999\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(m.vertices.size(), 3u);
  EXPECT_EQ(m.triangles.size(), 1u);
}

TEST(MeshIo, EncodersRejectIndicesOutOfRange) {
  TriMesh m = awkward_mesh();
  m.triangles.push_back({0, 1, 4});
  EXPECT_THROW(encode_obj(m), std::runtime_error);
  EXPECT_THROW(encode_mesh_ply(m), std::runtime_error);
}

}  // namespace
}  // namespace tear

namespace tear {
namespace {

TEST(MeshIo, StlRoundTripGivesEachTriangleItsOwnVertices) {
  const TriMesh m = awkward_mesh();
  const std::string bytes = encode_stl(m);
  ASSERT_EQ(bytes.size(), 84u + 50u * m.triangles.size());
  const TriMesh back = decode_stl(bytes);
  ASSERT_EQ(back.triangles.size(), m.triangles.size());
  ASSERT_EQ(back.vertices.size(), 3 * m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(back.triangles[t][k], int32_t(3 * t + k));
      EXPECT_EQ(back.vertices[3 * t + k], m.vertices[size_t(m.triangles[t][k])]);
    }
  // A binary file whose header happens to start with "solid" is still read as binary.
  std::string solid_header = bytes;
  solid_header.replace(0, 6, "solid ");
  EXPECT_EQ(decode_stl(solid_header).triangles.size(), m.triangles.size());
}

TEST(MeshIo, ReadsAsciiStlAndNamesItsErrors) {
  const std::string text =
      "solid two\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
      "      vertex 0 1 0\n    endloop\n  endfacet\n"
      "  facet normal 0 0 1\n    outer loop\n      vertex 1 0 0\n      vertex 1 1 0\n"
      "      vertex 0 1 0.5e0\n    endloop\n  endfacet\n"
      "endsolid two\n";
  const TriMesh m = decode_stl(text);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.vertices[5], Eigen::Vector3f(0, 1, 0.5f));
  EXPECT_EQ(error_of(decode_stl, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 q\n"),
            "bad STL: vertex 0 needs three numbers, got 'q'");
  EXPECT_EQ(error_of(decode_stl, "solid x\nvertex 0 0 0\nvertex 1 0 0\nendsolid\n"),
            "bad STL: 2 vertices, not a whole number of triangles");
  EXPECT_EQ(error_of(decode_stl, "hello"),
            "bad STL: neither binary (5 bytes do not match its triangle count) nor ascii (no "
            "'solid')");
}

TEST(MeshIo, ReadMeshFileChoosesByExtensionAndNamesTheFile) {
  const std::string dir = ::testing::TempDir() + "tear_mesh_io_read";
  std::filesystem::create_directories(dir);
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"a.obj", encode_obj(m)},
                                    {"a.PLY", encode_mesh_ply(m)}, {"a.stl", encode_stl(m)}}) {
    write_file_atomic(dir + "/" + name, bytes);
    EXPECT_EQ(read_mesh_file(dir + "/" + name).triangles.size(), 1u) << name;
  }
  auto error = [](const std::string& path) {
    try {
      read_mesh_file(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(dir + "/a.off"), "'" + dir + "/a.off': unknown mesh format '.off' (expected .obj, .ply or .stl)");
  EXPECT_EQ(error(dir + "/missing.obj").rfind(dir + "/missing.obj: cannot open", 0), 0u);
  write_file_atomic(dir + "/bad.obj", "v 0 0\n");
  EXPECT_EQ(error(dir + "/bad.obj"),
            "'" + dir + "/bad.obj': bad OBJ: line 1: vertex needs three numbers ('v 0 0')");
}

}  // namespace
}  // namespace tear
