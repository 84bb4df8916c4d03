// Volume mesh files: one two-tetrahedron mesh written by hand as gmsh MSH 4.1 (ASCII, and binary
// in both byte orders, with sparse node tags), TetGen .node/.ele (index base 1, attributes,
// markers) and VTU (ascii with skipped lower-dimensional cells, binary with UInt32 headers), all
// read as the same VolumeMesh; 2D variants; every refusal's message; the VTU writer's round trip.
#include "tear/io/volume_mesh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "io_fixture.h"
#include "tear/io/atomic_file.h"
#include "tear/io/endian.h"
#include "tear/io/vtk_xml.h"

namespace tear {
namespace {

using testing::HasSubstr;

// Nodes A B C D E and the tetrahedra ABCD, BCDE.
VolumeMesh two_tets() {
  VolumeMesh m;
  m.dim = 3;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  return m;
}

// Nodes A B C D in the plane and the triangles ABC, BDC.
VolumeMesh two_triangles() {
  VolumeMesh m;
  m.dim = 2;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.cells = {{0, 1, 2, 0}, {1, 3, 2, 0}};
  return m;
}

void expect_same_mesh(const VolumeMesh& a, const VolumeMesh& b) {
  EXPECT_EQ(a.dim, b.dim);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.cells, b.cells);
}

// The two tetrahedra with node tags A=10 B=20 C=3 D=7 E=100 in two entity blocks, elements of
// every lower dimension (skipped) and sections to skip. `tet_block` replaces the tet block.
std::string gmsh_ascii(const std::string& tet_block = "3 1 4 2\n5 10 20 3 7\n9 20 3 7 100\n") {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n"
         "$Entities\n1 0 0 1\n1 0 0 0 0\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
         "$Nodes\n2 5 3 100\n"
         "0 1 0 2\n10\n20\n0 0 0\n1 0 0\n"
         "3 1 0 3\n3\n7\n100\n0 1 0\n0 0 1\n1 1 1\n"
         "$EndNodes\n"
         "$Elements\n4 5 1 9\n"
         "0 1 15 1\n1 10\n"
         "1 1 1 1\n2 10 20\n"
         "2 1 2 1\n3 10 20 3\n" +
         tet_block + "$EndElements\n$NodeData\n1\n\"T\"\n$EndNodeData\n";
}

// The same mesh in binary, written value by value in the manual's layout.
std::string gmsh_binary(bool little) {
  std::string s = "$MeshFormat\n4.1 1 8\n";
  auto i32 = [&](int32_t v) { little ? append_le(&s, v) : append_be(&s, v); };
  auto u64 = [&](uint64_t v) { little ? append_le(&s, v) : append_be(&s, v); };
  auto f64 = [&](double v) { little ? append_le(&s, v) : append_be(&s, v); };
  i32(1);
  s += "\n$EndMeshFormat\n$Comments\nnot $Nodes\n$EndComments\n$Nodes\n";
  for (uint64_t v : {2, 5, 3, 100}) u64(v);
  i32(0), i32(1), i32(0), u64(2);
  u64(10), u64(20);
  for (double v : {0, 0, 0, 1, 0, 0}) f64(v);
  i32(3), i32(1), i32(0), u64(3);
  u64(3), u64(7), u64(100);
  for (double v : {0, 1, 0, 0, 0, 1, 1, 1, 1}) f64(v);
  s += "\n$EndNodes\n$Elements\n";
  for (uint64_t v : {3, 4, 1, 9}) u64(v);
  i32(1), i32(1), i32(1), u64(1);  // a line
  u64(2), u64(10), u64(20);
  i32(2), i32(1), i32(2), u64(1);  // a surface triangle
  u64(3), u64(10), u64(20), u64(3);
  i32(3), i32(1), i32(4), u64(2);
  for (uint64_t v : {5, 10, 20, 3, 7, 9, 20, 3, 7, 100}) u64(v);
  s += "\n$EndElements\n";
  return s;
}

std::string gmsh_error(const std::string& bytes) { return error_of(decode_gmsh, bytes); }

// `s` with the first `from` replaced by `to` (which must be there).
std::string edited(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

// The message with which `f(arg)` refuses its argument.
template <class F, class A>
std::string error_in(F f, const A& arg) {
  try {
    f(arg);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Gmsh, ReadsSparseTagsAndSkipsLowerDimensionsAndSections) {
  expect_same_mesh(decode_gmsh(gmsh_ascii()), two_tets());
}

TEST(Gmsh, BinaryInEitherByteOrderReadsAsAscii) {
  expect_same_mesh(decode_gmsh(gmsh_binary(true)), two_tets());
  expect_same_mesh(decode_gmsh(gmsh_binary(false)), two_tets());
}

TEST(Gmsh, TrianglesWithoutTetrahedraAre2D) {
  const std::string s =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n$EndNodes\n"
      "$Elements\n2 3 1 3\n1 1 1 1\n1 1 2\n2 1 2 2\n2 1 2 3\n3 2 4 3\n$EndElements\n";
  expect_same_mesh(decode_gmsh(s), two_triangles());
  std::string lifted = s;
  lifted.replace(lifted.find("1 1 0\n"), 6, "1 1 0.5\n");
  EXPECT_THAT(gmsh_error(lifted), HasSubstr("a 2D mesh must lie in the z = 0 plane (node 3"));
  std::string order2 = s;
  order2.replace(order2.find("2 1 2 2\n2 1 2 3\n3 2 4 3\n"), 24, "2 1 9 1\n2 1 2 3 4 1 2\n");
  EXPECT_THAT(
      gmsh_error(order2),
      HasSubstr("gmsh: line 20: element type 9 (6-node second order triangle) is not read"));
}

TEST(Gmsh, RefusesVersion2AndOtherFormats) {
  EXPECT_THAT(gmsh_error("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"),
              HasSubstr("gmsh: line 2: version 2.2 files are not read; save as MSH 4.1 (gmsh "
                        "-format msh41)"));
  EXPECT_THAT(gmsh_error("$MeshFormat\n4.1 0 4\n$EndMeshFormat\n"), HasSubstr("data-size '4'"));
  EXPECT_THAT(gmsh_error("solid x\n"), HasSubstr("does not begin with $MeshFormat"));
  EXPECT_THAT(gmsh_error(""), HasSubstr("does not begin with $MeshFormat"));
}

TEST(Gmsh, RefusesHigherOrderAndOtherSolidsByName) {
  EXPECT_THAT(gmsh_error(gmsh_ascii("3 1 11 1\n5 10 20 3 7 10 20 3 7 10 20\n")),
              HasSubstr("element type 11 (10-node second order tetrahedron) is not read: tear "
                        "reads 4-node tetrahedra (type 4) and 3-node triangles (type 2)"));
  EXPECT_THAT(gmsh_error(gmsh_ascii("3 1 5 2\n5 10 20 3 7 10 20 3 7\n6 10 20 3 7 10 20 3 7\n")),
              HasSubstr("element type 5 (8-node hexahedron) is not read"));
  EXPECT_THAT(gmsh_error(gmsh_ascii("3 1 42 1\n5 10 20 3 7\n")),
              HasSubstr("element type 42 (not a gmsh type"));
  // Surface quadrangles of a tet mesh are skipped like its triangles.
  std::string quads = gmsh_ascii("2 1 3 1\n4 10 20 3 7\n3 1 4 1\n5 10 20 3 7\n");
  quads.replace(quads.find("$Elements\n4 5 1 9"), 17, "$Elements\n5 5 1 9");
  const VolumeMesh m = decode_gmsh(quads);
  EXPECT_EQ(m.cells, (std::vector<std::array<uint32_t, 4>>{{0, 1, 2, 3}}));
}

TEST(Gmsh, NamesTheLineOfAMissingNode) {
  const std::string s = gmsh_ascii("3 1 4 2\n5 10 20 3 7\n9 20 3 7 99\n");
  const size_t line =
      size_t(std::count(s.begin(), s.begin() + long(s.find("9 20 3 7 99")), '\n')) + 1;
  EXPECT_THAT(gmsh_error(s), HasSubstr("gmsh: line " + std::to_string(line) +
                                       ": element 9 names node 99, the file has 5 nodes"));
}

TEST(Gmsh, RefusesInconsistentCountsAndTags) {
  EXPECT_THAT(gmsh_error(edited(gmsh_ascii(), "$Nodes\n2 5", "$Nodes\n2 6")),
              HasSubstr("the entity blocks hold 5 nodes, the header says 6"));
  EXPECT_THAT(gmsh_error(edited(gmsh_ascii(), "\n7\n100\n", "\n7\n3\n")),
              HasSubstr("node tag 3 appears twice"));
  EXPECT_THAT(gmsh_error(edited(gmsh_ascii(), "$EndEntities", "$EndEntitie")),
              HasSubstr("$Entities is not closed by $EndEntities"));
  EXPECT_THAT(gmsh_error(edited(gmsh_ascii(), "0 1 0 2\n", "0 1 0 999999999999\n")),
              HasSubstr("999999999999 nodes do not fit"));
}

TEST(Gmsh, BinaryRefusesLyingCountsAndTruncationByOffset) {
  const std::string good = gmsh_binary(true);
  std::string s = good;
  // The first block's node count (after its three ints) claims 2^40 nodes.
  const size_t at = good.find("\n$Nodes\n") + 8 + 4 * 8 + 3 * 4;
  store_le<uint64_t>(&s[at], uint64_t(1) << 40);
  EXPECT_THAT(gmsh_error(s),
              HasSubstr("gmsh: byte " + std::to_string(at) + ": 1099511627776 nodes do not fit"));
  EXPECT_THAT(gmsh_error(good.substr(0, good.find("$Elements\n") + 10 + 20)),
              HasSubstr("the file ends inside the smallest element tag"));
  s = good;
  store_le<int32_t>(&s[good.find("8\n") + 2], 7);
  EXPECT_THAT(gmsh_error(s), HasSubstr("the endianness int is not 1"));
}

// TetGen: base 1, one attribute and a marker per node, a region attribute per element.
const char* kTetgenNode =
    "# two tets\n5 3 1 1\n1 0 0 0 0.5 1\n2 1 0 0 0.5 1\n3 0 1 0 0.5 0  # a comment\n"
    "4 0 0 1 0.5 0\n\n5 1 1 1 0.5 1\n";
const char* kTetgenEle = "2 4 1\n1 1 2 3 4 7\n2 2 3 4 5 7\n# end\n";

std::string tetgen_error(const std::string& node, const std::string& ele) {
  try {
    decode_tetgen(node, ele);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Tetgen, ReadsBaseOneWithAttributesAndMarkers) {
  expect_same_mesh(decode_tetgen(kTetgenNode, kTetgenEle), two_tets());
  // Base 0, no attributes.
  expect_same_mesh(decode_tetgen("5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n",
                                 "2 4 0\n0 0 1 2 3\n1 1 2 3 4\n"),
                   two_tets());
}

TEST(Tetgen, TriangleFilesAre2D) {
  expect_same_mesh(
      decode_tetgen("4 2 0 1\n1 0 0 1\n2 1 0 1\n3 0 1 1\n4 1 1 0\n", "2 3 0\n1 1 2 3\n2 2 4 3\n"),
      two_triangles());
}

TEST(Tetgen, RefusesWithFileAndLine) {
  EXPECT_THAT(tetgen_error(kTetgenNode, "2 10 0\n"),
              HasSubstr("tetgen .ele: line 1: 10-node (second order) elements are not read"));
  EXPECT_THAT(tetgen_error(kTetgenNode, "2 4 1\n1 1 2 3 4 7\n2 2 3 4 9 7\n"),
              HasSubstr("tetgen .ele: line 3: element 2 names node 9, the .node file has 5 nodes "
                        "numbered from 1"));
  EXPECT_THAT(tetgen_error("2 3 0 0\n1 0 0 0\n3 1 0 0\n", kTetgenEle),
              HasSubstr("tetgen .node: line 3: node 2 has index 3, expected 2"));
  EXPECT_THAT(tetgen_error("99999999 3 0 0\n1 0 0 0\n", kTetgenEle),
              HasSubstr("99999999 nodes do not fit"));
  EXPECT_THAT(tetgen_error("2 3 0 0\n1 0 0 0\n2 1 0\n", kTetgenEle),
              HasSubstr("the file ends where a coordinate should be"));
  EXPECT_THAT(tetgen_error(kTetgenNode, "1 4 0\n1 1 2 3 4\n5 5 5 5 5\n"),
              HasSubstr("more data after the 1 elements"));
  EXPECT_THAT(tetgen_error("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 1\n", "1 3 0\n1 1 2 3\n"),
              HasSubstr("a 2D mesh must lie in the z = 0 plane"));
}

// The two tetrahedra as an ascii VTU with a vertex and a triangle cell (skipped), a velocity
// per point and an energy per cell.
std::string vtu_ascii(const std::string& types = "1 10 5 10") {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n"
         "<UnstructuredGrid><Piece NumberOfPoints=\"5\" NumberOfCells=\"4\">\n"
         "<PointData><DataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\" "
         "format=\"ascii\">0 0 0 1 0 0 2 0 0 3 0 0 4 0 0</DataArray></PointData>\n"
         "<CellData><DataArray type=\"Float64\" Name=\"energy\" format=\"ascii\">9 0.5 8 "
         "0.25</DataArray></CellData>\n"
         "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
         "0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray></Points>\n"
         "<Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">4 0 1 2 3 0 1 "
         "2 1 2 3 4</DataArray>\n"
         "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">1 5 8 12</DataArray>\n"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">" +
         types + "</DataArray></Cells>\n</Piece></UnstructuredGrid></VTKFile>\n";
}

// The same two tetrahedra in binary with UInt32 headers (VTK's default), Int64 cells.
std::string vtu_binary() {
  auto array = [](const std::string& attrs, const std::string& raw) {
    std::string block;
    append_le<uint32_t>(&block, uint32_t(raw.size()));
    return "<DataArray " + attrs + " format=\"binary\">" + base64_encode(block + raw) +
           "</DataArray>\n";
  };
  std::string points, connectivity, offsets, types;
  for (float v : {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}) append_le(&points, v);
  for (int64_t v : {0, 1, 2, 3, 1, 2, 3, 4}) append_le(&connectivity, v);
  for (int64_t v : {4, 8}) append_le(&offsets, v);
  types = "\x0a\x0a";
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>"
         "<Piece NumberOfPoints=\"5\" NumberOfCells=\"2\">\n<Points>" +
         array("type=\"Float32\" NumberOfComponents=\"3\"", points) + "</Points><Cells>" +
         array("type=\"Int64\" Name=\"connectivity\"", connectivity) +
         array("type=\"Int64\" Name=\"offsets\"", offsets) +
         array("type=\"UInt8\" Name=\"types\"", types) +
         "</Cells></Piece></UnstructuredGrid></VTKFile>\n";
}

std::string vtu_error(const std::string& bytes) { return error_of(decode_volume_vtu, bytes); }

TEST(VolumeVtu, AsciiAndBinaryReadAsTheOtherFormats) {
  const VolumeMesh a = decode_volume_vtu(vtu_ascii());
  expect_same_mesh(a, two_tets());
  expect_same_mesh(decode_volume_vtu(vtu_binary()), two_tets());
  // The columns of the kept cells only.
  EXPECT_EQ(a.node_columns.names, (std::vector<std::string>{"vx", "vy", "vz"}));
  EXPECT_EQ(a.node_columns.column("vx"), (std::vector<double>{0, 1, 2, 3, 4}));
  EXPECT_EQ(a.cell_columns.count, 2u);
  EXPECT_EQ(a.cell_columns.column("energy"), (std::vector<double>{0.5, 0.25}));
}

TEST(VolumeVtu, TrianglesWithoutSolidsAre2D) {
  std::string s = vtu_ascii("1 5 5 5");
  s.replace(s.find("4 0 1 2 3 0 1 2 1 2 3 4"), 23, "4 0 1 2 0 1 3 1 3 2");
  s.replace(s.find("1 5 8 12"), 8, "1 4 7 10");
  s.replace(s.find("0 0 0 1 0 0 0 1 0 0 0 1 1 1 1"), 29, "0 0 0 1 0 0 0 1 0 1 1 0 5 5 0");
  const VolumeMesh m = decode_volume_vtu(s);
  EXPECT_EQ(m.dim, 2);
  EXPECT_EQ(m.cells,
            (std::vector<std::array<uint32_t, 4>>{{0, 1, 2, 0}, {0, 1, 3, 0}, {1, 3, 2, 0}}));
  EXPECT_EQ(m.cell_columns.column("energy"), (std::vector<double>{0.5, 8, 0.25}));
}

TEST(VolumeVtu, RefusesOtherSolidsCompressionAndBadIndices) {
  EXPECT_THAT(vtu_error(vtu_ascii("1 24 5 10")), HasSubstr("cell 1 is VTK_QUADRATIC_TETRA (24)"));
  EXPECT_THAT(
      vtu_error(vtu_ascii("1 10 5 12")),
      HasSubstr("cell 3 is VTK_HEXAHEDRON (12): tear reads VTK_TETRA (10) and VTK_TRIANGLE (5)"));
  EXPECT_THAT(vtu_error(vtu_ascii("1 10 5 99")), HasSubstr("cell 3 has type 99"));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), "version=\"0.1\"",
                               "version=\"0.1\" compressor=\"vtkZLibDataCompressor\"")),
              HasSubstr("compressed VTU is not read (save uncompressed)"));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), "2 1 2 3 4", "2 1 2 3 5")),
              HasSubstr("connectivity value 11 is 5 (0 to 4)"));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), "9 0.5 8 0.25", "9 0.5 8")),
              HasSubstr("array 'energy' has 3 values, expected 4 cells"));
  EXPECT_THAT(vtu_error(vtu_ascii("1 1 3 3")), HasSubstr("no tetrahedra or triangles"));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), "format=\"ascii\">0 0 0 1 0 0 0 1",
                               "offset=\"0\" format=\"ascii\">0 0 0 1 0 0 0 1")),
              HasSubstr("appended data"));
}

TEST(VolumeVtu, AsciiValuesAreWhatTheirTypeHolds) {
  // A Float32 array's 0.1 is float(0.1), so that writing it as Float32 again keeps it (a fuzz
  // finding: 4.4e59 came back as inf); integers must be whole and in range.
  const VolumeMesh m = decode_volume_vtu(edited(vtu_ascii(), ">0 0 0 1 0 0 2", ">0.1 0 0 1 0 0 2"));
  EXPECT_EQ(m.node_columns.column("vx")[0], double(0.1f));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), ">0 0 0 1 0 0 2", ">4e59 0 0 1 0 0 2")),
              HasSubstr("array 'velocity': ascii value 4e59 is not a Float32"));
  EXPECT_THAT(vtu_error(edited(vtu_ascii(), ">4 0 1 2 3", ">4.5 0 1 2 3")),
              HasSubstr("array 'connectivity': ascii value 4.5 is not a Int32"));
}

TEST(VolumeVtu, RoundTripsColumns) {
  for (int dim : {3, 2}) {
    VolumeMesh m = dim == 3 ? two_tets() : two_triangles();
    const size_t n = m.nodes.size();
    m.nodes[1][0] = 0.1;  // a double that float would change
    m.node_columns.count = n;
    m.node_columns.add("vx", ColumnType::Float32, std::vector<double>(n, 0.5));
    m.node_columns.add("vy", ColumnType::Float32, std::vector<double>(n, -1));
    m.node_columns.add("vz", ColumnType::Float32, std::vector<double>(n, 2));
    std::vector<double> ids(n);
    for (size_t i = 0; i < n; ++i) ids[i] = double(i) + 100;
    m.node_columns.add("id", ColumnType::Int32, ids);
    m.cell_columns.count = 2;
    m.cell_columns.add("energy", ColumnType::Float64, {0.1, 0.2});
    m.cell_columns.add("fx", ColumnType::Float32, {1, 0});
    m.cell_columns.add("fy", ColumnType::Float32, {0, 1});
    m.cell_columns.add("fz", ColumnType::Float32, {0, 0});
    m.cell_columns.add("stress_xx", ColumnType::Float32, {-3.5, 4.25});
    const std::string bytes = encode_volume_vtu(m);
    EXPECT_THAT(bytes, HasSubstr("Name=\"velocity\" NumberOfComponents=\"3\""));
    EXPECT_THAT(bytes, HasSubstr("Name=\"fiber\" NumberOfComponents=\"3\""));
    const VolumeMesh d = decode_volume_vtu(bytes);
    expect_same_mesh(d, m);
    for (const PointTable* t : {&m.node_columns, &m.cell_columns}) {
      const PointTable& u = t == &m.node_columns ? d.node_columns : d.cell_columns;
      EXPECT_EQ(u.names, t->names);
      EXPECT_EQ(u.types, t->types);
      for (const std::string& name : t->names) EXPECT_EQ(u.column(name), t->column(name)) << name;
    }
  }
}

TEST(VolumeVtu, WriterRefusesInconsistentMeshes) {
  VolumeMesh m = two_tets();
  m.cells[1][3] = 5;
  EXPECT_THAT(error_in(encode_volume_vtu, m),
              HasSubstr("cell 1 names node 5, the mesh has 5 nodes"));
  m = two_tets();
  m.node_columns.count = 5;
  m.node_columns.add("x", ColumnType::Float32, std::vector<double>(5, 0));
  EXPECT_THAT(error_in(encode_volume_vtu, m), HasSubstr("a node column 'x'"));
  m = two_tets();
  m.cell_columns.count = 1;
  m.cell_columns.add("energy", ColumnType::Float32, {1});
  EXPECT_THAT(error_in(encode_volume_vtu, m), HasSubstr("1 rows of cell columns for 2 cells"));
}

TEST(ReadVolumeMesh, ChoosesByExtensionAndNamesThePath) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "volume_mesh_files";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& bytes) {
    write_file_atomic((dir / name).string(), bytes);
    return (dir / name).string();
  };
  expect_same_mesh(read_volume_mesh(write("a.msh", gmsh_binary(true))), two_tets());
  expect_same_mesh(read_volume_mesh(write("a.vtu", vtu_ascii())), two_tets());
  write("t.node", kTetgenNode);
  const std::string ele = write("t.ele", kTetgenEle);
  expect_same_mesh(read_volume_mesh(ele), two_tets());
  expect_same_mesh(read_volume_mesh((dir / "t.node").string()), two_tets());

  const std::string bad = write("bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  EXPECT_THAT(error_of(read_volume_mesh, bad), HasSubstr(bad + ": gmsh: line 2: version 2.2"));
  write("u.node", kTetgenNode);
  const std::string bad_ele = write("u.ele", "2 4 1\n1 1 2 3 4 7\n2 2 3 4 9 7\n");
  EXPECT_THAT(error_of(read_volume_mesh, (dir / "u.node").string()),
              HasSubstr(bad_ele + ": line 3: element 2 names node 9"));
  EXPECT_THAT(error_of(read_volume_mesh, (dir / "none.node").string()), HasSubstr("none.node"));
  EXPECT_THAT(error_of(read_volume_mesh, (dir / "a.obj").string()),
              HasSubstr("a.obj: not a volume mesh file (tear reads .msh, .node/.ele and .vtu)"));
}

}  // namespace
}  // namespace tear
