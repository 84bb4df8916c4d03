#include "tear/io/volume_mesh.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/endian.h"
#include "tear/io/numbers.h"
#include "tear/io/point_groups.h"
#include "tear/io/vtk_xml.h"

namespace tear {

void check_volume_mesh(const VolumeMesh& m, const std::string& context) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(context + why); };
  if (m.dim != 2 && m.dim != 3) fail("dimension " + std::to_string(m.dim) + " (2 or 3)");
  if (m.cells.empty()) fail(m.dim == 3 ? "no tetrahedra" : "no triangles");
  if (m.nodes.size() > UINT32_MAX) fail("more than 2^32 - 1 nodes");
  const int k = corners(m);
  for (size_t e = 0; e < m.cells.size(); ++e)
    for (int c = 0; c < k; ++c)
      if (m.cells[e][size_t(c)] >= m.nodes.size())
        fail("cell " + std::to_string(e) + " names node " + std::to_string(m.cells[e][size_t(c)]) +
             ", the mesh has " + std::to_string(m.nodes.size()) + " nodes");
  if (m.dim == 2)
    for (size_t i = 0; i < m.nodes.size(); ++i)
      if (m.nodes[i][2] != 0)
        fail("a 2D mesh must lie in the z = 0 plane (node " + std::to_string(i) +
             " has z = " + shortest_text(m.nodes[i][2]) + ")");
  auto check_table = [&](const PointTable& t, size_t rows, const char* what) {
    if (t.names.empty() && t.columns.empty()) return;
    t.check_shape();
    if (t.count != rows)
      fail(std::to_string(t.count) + " rows of " + what + " columns for " + std::to_string(rows) +
           " " + what + "s");
  };
  check_table(m.node_columns, m.nodes.size(), "node");
  check_table(m.cell_columns, m.cells.size(), "cell");
  for (const char* n : {"x", "y", "z"})
    if (m.node_columns.has(n))
      fail(std::string("a node column '") + n + "' (the nodes are the positions)");
}

namespace {

// VTK's cell types (vtkCellType.h): dimension and point count (0: any).
struct VtkCell {
  int type, dim, points;
  const char* name;
};

const VtkCell kVtkCells[] = {
    {1, 0, 1, "VTK_VERTEX"},
    {2, 0, 0, "VTK_POLY_VERTEX"},
    {3, 1, 2, "VTK_LINE"},
    {4, 1, 0, "VTK_POLY_LINE"},
    {5, 2, 3, "VTK_TRIANGLE"},
    {6, 2, 0, "VTK_TRIANGLE_STRIP"},
    {7, 2, 0, "VTK_POLYGON"},
    {8, 2, 4, "VTK_PIXEL"},
    {9, 2, 4, "VTK_QUAD"},
    {10, 3, 4, "VTK_TETRA"},
    {11, 3, 8, "VTK_VOXEL"},
    {12, 3, 8, "VTK_HEXAHEDRON"},
    {13, 3, 6, "VTK_WEDGE"},
    {14, 3, 5, "VTK_PYRAMID"},
    {15, 3, 10, "VTK_PENTAGONAL_PRISM"},
    {16, 3, 12, "VTK_HEXAGONAL_PRISM"},
    {21, 1, 3, "VTK_QUADRATIC_EDGE"},
    {22, 2, 6, "VTK_QUADRATIC_TRIANGLE"},
    {23, 2, 8, "VTK_QUADRATIC_QUAD"},
    {24, 3, 10, "VTK_QUADRATIC_TETRA"},
    {25, 3, 20, "VTK_QUADRATIC_HEXAHEDRON"},
    {26, 3, 15, "VTK_QUADRATIC_WEDGE"},
    {27, 3, 13, "VTK_QUADRATIC_PYRAMID"},
    {28, 2, 9, "VTK_BIQUADRATIC_QUAD"},
    {29, 3, 27, "VTK_TRIQUADRATIC_HEXAHEDRON"},
    {42, 3, 0, "VTK_POLYHEDRON"},
    {68, 1, 0, "VTK_LAGRANGE_CURVE"},
    {69, 2, 0, "VTK_LAGRANGE_TRIANGLE"},
    {70, 2, 0, "VTK_LAGRANGE_QUADRILATERAL"},
    {71, 3, 0, "VTK_LAGRANGE_TETRAHEDRON"},
    {72, 3, 0, "VTK_LAGRANGE_HEXAHEDRON"},
    {73, 3, 0, "VTK_LAGRANGE_WEDGE"},
    {74, 3, 0, "VTK_LAGRANGE_PYRAMID"},
};
constexpr int kVtkTriangle = 5, kVtkTetra = 10;

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error("bad VTU: " + why); }

const VtkArray& cells_array(const VtkPiece& piece, const char* name) {
  for (const VtkArray& a : piece.arrays)
    if (a.parent == "Cells" && a.name == name) {
      if (a.components != 1) fail(std::string("the ") + name + " array has several components");
      return a;
    }
  fail(std::string("no ") + name + " array in <Cells>");
}

// A value of an integer array (connectivity, offsets, types) as a count below `limit`.
size_t index_value(const VtkArray& a, size_t i, size_t limit) {
  const double v = a.values[i];
  if (!(v >= 0 && v < double(limit)) || v != std::floor(v))
    fail(a.name + " value " + std::to_string(i) + " is " + shortest_text(v) + " (0 to " +
         std::to_string(limit - 1) + ")");
  return size_t(v);
}

}  // namespace

VolumeMesh decode_volume_vtu(const std::string& bytes) {
  const VtkPiece piece = read_vtk_piece(bytes, [](const std::string&) { return true; });
  VolumeMesh m;
  const auto p = std::find_if(piece.arrays.begin(), piece.arrays.end(),
                              [](const VtkArray& a) { return a.parent == "Points"; });
  if (p == piece.arrays.end()) fail("no <Points> array");
  if (p->components != 3)
    fail("the Points array has " + std::to_string(p->components) + " components, not 3");
  if (p->values.size() / 3 != piece.points)
    fail("the Points array has " + std::to_string(p->values.size() / 3) + " points, the Piece " +
         std::to_string(piece.points));
  if (piece.points > UINT32_MAX) fail("more than 2^32 - 1 points");
  m.nodes.resize(piece.points);
  for (size_t i = 0; i < piece.points; ++i)
    for (size_t k = 0; k < 3; ++k) {
      m.nodes[i][k] = p->values[3 * i + k];
      if (!std::isfinite(m.nodes[i][k]))
        fail("point " + std::to_string(i) + " has a coordinate that is not finite");
    }

  const VtkArray& connectivity = cells_array(piece, "connectivity");
  const VtkArray& offsets = cells_array(piece, "offsets");
  const VtkArray& types = cells_array(piece, "types");
  const size_t n = piece.cells;
  if (types.values.size() != n)
    fail("the types array has " + std::to_string(types.values.size()) + " values for " +
         std::to_string(n) + " cells");
  // VTK writes the end of each cell; a leading 0 (the start of the first) is allowed.
  const size_t skip = offsets.values.size() == n + 1 && n > 0 && offsets.values[0] == 0 ? 1 : 0;
  if (offsets.values.size() != n + skip)
    fail("the offsets array has " + std::to_string(offsets.values.size()) + " values for " +
         std::to_string(n) + " cells");
  // The cells' types, their dimension (the highest) and their ranges in `connectivity`.
  std::vector<const VtkCell*> type(n);
  int dim = -1;
  for (size_t e = 0; e < n; ++e) {
    const size_t t = index_value(types, e, 256);
    const VtkCell* c = nullptr;
    for (const VtkCell& k : kVtkCells)
      if (k.type == int(t)) c = &k;
    if (!c)
      fail("cell " + std::to_string(e) + " has type " + std::to_string(t) +
           " (not a VTK cell type this reader knows)");
    type[e] = c;
    dim = std::max(dim, c->dim);
  }
  if (dim < 2) fail("no tetrahedra or triangles");
  const int keep = dim == 3 ? kVtkTetra : kVtkTriangle;
  m.dim = dim;
  std::vector<size_t> kept;
  size_t begin = 0;
  for (size_t e = 0; e < n; ++e) {
    const size_t end = index_value(offsets, e + skip, connectivity.values.size() + 1);
    if (end < begin) fail("the offsets decrease at cell " + std::to_string(e));
    if (type[e]->dim == dim && type[e]->type != keep)
      fail("cell " + std::to_string(e) + " is " + type[e]->name + " (" +
           std::to_string(type[e]->type) +
           "): tear reads VTK_TETRA (10) and VTK_TRIANGLE (5) cells");
    if (type[e]->points != 0 && end - begin != size_t(type[e]->points))
      fail("cell " + std::to_string(e) + " (" + type[e]->name + ") has " +
           std::to_string(end - begin) + " points, not " + std::to_string(type[e]->points));
    if (type[e]->type == keep) {
      std::array<uint32_t, 4> cell{0, 0, 0, 0};
      for (size_t c = 0; c < end - begin; ++c)
        cell[c] = uint32_t(index_value(connectivity, begin + c, piece.points));
      m.cells.push_back(cell);
      kept.push_back(e);
    }
    begin = end;
  }
  if (begin != connectivity.values.size())
    fail("the connectivity array has " + std::to_string(connectivity.values.size()) +
         " values, the offsets end at " + std::to_string(begin));

  m.node_columns.count = piece.points;
  m.cell_columns.count = kept.size();
  ColumnNames node_names, cell_names;
  for (const VtkArray& a : piece.arrays) {
    if (a.parent != "PointData" && a.parent != "CellData") continue;
    if (a.name.empty()) fail("a " + a.parent + " array without a Name");
    if (a.parent == "PointData")
      add_vtk_columns(a, piece.points, "points", nullptr, &m.node_columns, &node_names);
    else
      add_vtk_columns(a, n, "cells", &kept, &m.cell_columns, &cell_names);
  }
  check_volume_mesh(m, "bad VTU: ");
  return m;
}

std::string encode_volume_vtu(const VolumeMesh& m) {
  check_volume_mesh(m);
  const int k = corners(m);
  std::string out = vtk_grid_begin(m.nodes.size(), m.cells.size());
  auto data = [&](const char* element, const PointTable& t, size_t rows) {
    out += std::string("      <") + element + ">\n";
    if (!t.names.empty())
      for (const PointAttribute& a : group_columns(t, AttributeFormat::Vtu))
        write_vtk_array(&out, "        ", a.name, vtk_type_name(a), a.components.size(),
                        vtk_attribute_bytes(a, rows));
    out += std::string("      </") + element + ">\n";
  };
  data("PointData", m.node_columns, m.nodes.size());
  data("CellData", m.cell_columns, m.cells.size());
  std::string points, connectivity, offsets,
      types(m.cells.size(), char(m.dim == 3 ? kVtkTetra : kVtkTriangle));
  points.reserve(24 * m.nodes.size());
  for (const auto& x : m.nodes)
    for (double c : x) append_le(&points, c);
  connectivity.reserve(8 * size_t(k) * m.cells.size());
  for (size_t e = 0; e < m.cells.size(); ++e) {
    for (int c = 0; c < k; ++c) append_le<int64_t>(&connectivity, m.cells[e][size_t(c)]);
    append_le<int64_t>(&offsets, int64_t(e + 1) * k);
  }
  out += "      <Points>\n";
  write_vtk_array(&out, "        ", "Points", "Float64", 3, points);
  out += "      </Points>\n";
  write_vtk_cells_and_end(&out, connectivity, offsets, types);
  return out;
}

VolumeMesh read_volume_mesh(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".node" || ext == ".ele") {
    const std::string stem = path.substr(0, path.size() - ext.size());
    const std::string node = stem + ".node", ele = stem + ".ele";
    const std::string node_text = read_file(node);
    return decode_tetgen(node_text, read_file(ele), node, ele);
  }
  if (ext != ".msh" && ext != ".vtu")
    throw std::runtime_error(path +
                             ": not a volume mesh file (tear reads .msh, .node/.ele and .vtu)");
  const std::string bytes = read_file(path);
  try {
    return ext == ".msh" ? decode_gmsh(bytes) : decode_volume_vtu(bytes);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace tear
