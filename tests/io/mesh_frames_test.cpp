// The codimensional parts of frames (io/mesh_frames.h): PLY reads back as written, OBJ reads
// back through the mesh reader, VTU and Houdini's GEO hold the cells and arrays they say, bad
// parts are refused.
#include "tear/io/mesh_frames.h"

#include <gtest/gtest.h>


#include "tear/io/mesh_io.h"

namespace tear {
namespace {

MeshPart sample_part(int corners) {
  MeshPart p;
  p.name = corners == 3 ? "surfaces" : "curves";
  p.corners = corners;
  p.vertices.count = 4;
  p.vertices.add("id", ColumnType::Int32, {0, 1, 2, 3});
  p.vertices.add("x", ColumnType::Float32, {0, 1, 1, 0});
  p.vertices.add("y", ColumnType::Float32, {0, 0, 1, 1});
  p.vertices.add("z", ColumnType::Float32, {0.5, 0.5, 0.25, 0.125});
  p.vertices.add("vx", ColumnType::Float32, {1, 2, 3, 4});
  p.vertices.add("vy", ColumnType::Float32, {0, 0, 0, 0});
  p.vertices.add("vz", ColumnType::Float32, {-1, -2, -3, -4});
  p.vertices.add("material", ColumnType::UInt8, {2, 2, 2, 2});
  if (corners == 3)
    p.elements = {{0, 1, 2}, {0, 2, 3}};
  else
    p.elements = {{0, 1, 0}, {1, 2, 0}};
  p.element_columns.count = 2;
  p.element_columns.add("id", ColumnType::Int32, {0, 1});
  p.element_columns.add("contact", ColumnType::UInt8, {1, 2});
  p.element_columns.add("normal_stretch", ColumnType::Float32, {0.75, 1});
  return p;
}

TEST(MeshFrames, PlyReadsBackAsWritten) {
  for (int corners : {2, 3}) {
    const MeshPart p = sample_part(corners);
    const MeshPart q = decode_mesh_part_ply(encode_mesh_part_ply(p));
    EXPECT_EQ(q.corners, corners);
    EXPECT_EQ(q.vertices.names, p.vertices.names);
    EXPECT_EQ(q.vertices.types, p.vertices.types);
    EXPECT_EQ(q.vertices.columns, p.vertices.columns);
    EXPECT_EQ(q.element_columns.names, p.element_columns.names);
    EXPECT_EQ(q.element_columns.columns, p.element_columns.columns);
    for (size_t k = 0; k < p.elements.size(); ++k)
      for (int c = 0; c < corners; ++c)
        EXPECT_EQ(q.elements[k][size_t(c)], p.elements[k][size_t(c)]);
    // The general mesh reader takes the same file: faces, or edges as segments.
    const TriMesh m = decode_mesh_ply(encode_mesh_part_ply(p));
    EXPECT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(corners == 3 ? m.triangles.size() : m.segments.size(), 2u);
  }
}

TEST(MeshFrames, ObjReadsBackThroughTheMeshReader) {
  const TriMesh faces = decode_obj(encode_mesh_part_obj(sample_part(3)));
  EXPECT_EQ(faces.vertices.size(), 4u);
  EXPECT_EQ(faces.vertices[2], Eigen::Vector3f(1, 1, 0.25f));
  EXPECT_EQ(faces.triangles, (std::vector<std::array<int32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
  const TriMesh lines = decode_obj(encode_mesh_part_obj(sample_part(2)));
  EXPECT_EQ(lines.segments, (std::vector<std::array<int32_t, 2>>{{0, 1}, {1, 2}}));
  EXPECT_TRUE(lines.triangles.empty());
}

TEST(MeshFrames, VtuHoldsTheCellsAndArrays) {
  for (int corners : {2, 3}) {
    const std::string x = encode_mesh_part_vtu(sample_part(corners));
    EXPECT_NE(x.find("NumberOfPoints=\"4\" NumberOfCells=\"2\""), std::string::npos);
    const std::string types = corners == 3 ? "5 5 " : "3 3 ";
    EXPECT_NE(x.find("Name=\"types\" format=\"ascii\">" + types + "<"), std::string::npos) << x;
    const std::string offsets = corners == 3 ? "3 6 " : "2 4 ";
    EXPECT_NE(x.find("Name=\"offsets\" format=\"ascii\">" + offsets + "<"), std::string::npos);
    const std::string connectivity = corners == 3 ? "0 1 2 0 2 3 " : "0 1 1 2 ";
    EXPECT_NE(x.find("Name=\"connectivity\" format=\"ascii\">" + connectivity + "<"),
              std::string::npos);
    EXPECT_NE(x.find("Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">1 0 -1 2 0 -2"),
              std::string::npos);
    EXPECT_NE(x.find("Name=\"contact\" format=\"ascii\">1 2 <"), std::string::npos);
    EXPECT_NE(x.find("Name=\"normal_stretch\" format=\"ascii\">0.75 1 <"), std::string::npos);
    EXPECT_EQ(x.find("Name=\"vx\""), std::string::npos);  // inside velocity
    // Well nested: every opened DataArray closes.
    auto count = [&](const std::string& what) {
      size_t n = 0;
      for (size_t at = x.find(what); at != std::string::npos; at = x.find(what, at + 1)) ++n;
      return n;
    };
    const size_t open = count("<DataArray"), close = count("</DataArray>");
    EXPECT_EQ(open, 10u);
    EXPECT_EQ(open, close);
  }
}

// Houdini's classic ASCII geometry: the header's counts, the attribute dictionaries, a point
// line and a primitive line of each kind, exactly.
TEST(MeshFrames, GeoHoldsThePointsAndPolygons) {
  for (int corners : {2, 3}) {
    const std::string g = encode_mesh_part_geo(sample_part(corners));
    EXPECT_EQ(g.rfind("PGEOMETRY V5\nNPoints 4 NPrims 2\nNPointGroups 0 NPrimGroups 0\n"
                      "NPointAttrib 3 NVertexAttrib 0 NPrimAttrib 3 NAttrib 0\n"
                      "PointAttrib\nid 1 int 0\nv 3 float 0 0 0\nmaterial 1 int 0\n"
                      "0 0 0.5 1 (0 1 0 -1 2)\n1 0 0.5 1 (1 2 0 -2 2)\n",
                      0),
              0u)
        << g;
    EXPECT_NE(g.find("\n0 1 0.125 1 (3 4 0 -4 2)\nPrimitiveAttrib\nid 1 int 0\ncontact 1 int 0\n"
                     "normal_stretch 1 float 0\nRun 2 Poly\n"),
              std::string::npos)
        << g;
    const std::string prims = corners == 3 ? "3 < 0 1 2 [0 1 0.75]\n3 < 0 2 3 [1 2 1]\n"
                                           : "2 : 0 1 [0 1 0.75]\n2 : 1 2 [1 2 1]\n";
    EXPECT_NE(g.find("Run 2 Poly\n" + prims + "beginExtra\nendExtra\n"), std::string::npos) << g;
  }
  EXPECT_EQ(encode_mesh_part(sample_part(3), "geo"), encode_mesh_part_geo(sample_part(3)));
}

TEST(MeshFrames, PartsThatDoNotAddUpAreRefused) {
  MeshPart p = sample_part(3);
  p.elements[1][2] = 4;
  for (const char* f : {"ply", "obj", "vtu"}) {
    try {
      encode_mesh_part(p, f);
      ADD_FAILURE() << f;
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "mesh part 'surfaces': element 1 uses vertex 4 of 4") << f;
    }
  }
  MeshPart q = sample_part(2);
  q.element_columns.count = 3;
  EXPECT_THROW(encode_mesh_part_ply(q), std::runtime_error);
  EXPECT_THROW(encode_mesh_part(sample_part(2), "bgeo"), std::runtime_error);
}

}  // namespace
}  // namespace tear
