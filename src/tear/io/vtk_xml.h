// io/: the pieces of VTK's XML format that the point-cloud VTU (io/vtu.h) and the volume-mesh
// VTU (io/volume_mesh.h) share: base64, XML escapes, a strict reader of one unstructured-grid
// Piece's DataArrays (inline binary or ascii), and the writer of one binary DataArray.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tear/io/numbers.h"
#include "tear/io/point_groups.h"

namespace tear {

// RFC 4648 with padding.
std::string base64_encode(const std::string& in);
std::string xml_escape(const std::string& s);

// One DataArray of a Piece.
struct VtkArray {
  std::string parent;  // the enclosing element: PointData, Points, Cells, CellData, FieldData
  std::string name;
  size_t components = 1;
  std::string type;  // "Float32", "Int64", ...
  NumberType number = NumberType::Float64;
  std::vector<double> values;  // read only for the parents the caller asked for
};

struct VtkPiece {
  size_t points = 0, cells = 0;  // NumberOfPoints, NumberOfCells (0 where absent)
  std::vector<VtkArray> arrays;  // in file order
};

// Reads the single Piece of a <VTKFile type="UnstructuredGrid"> (byte_order LittleEndian,
// header_type UInt32 or UInt64), with the values of the arrays whose parent `read(parent)`
// accepts. Throws std::runtime_error("bad VTU: ...") for anything else: compressed or
// appended data, several pieces, malformed XML, a lying base64 header.
VtkPiece read_vtk_piece(const std::string& bytes,
                        const std::function<bool(const std::string&)>& read);

// The columns an array of `tuples` tuples (`what`: "points", "cells") gives, named by
// attribute_columns() (VTU flavour), of the array's exact type, with the tuples `rows` (each
// below `tuples`; nullptr: all of them) as their rows, added to `t`. Throws
// std::runtime_error("bad VTU: ...") on a wrong size, a repeated or over-long name, more than
// kMaxColumns columns.
void add_vtk_columns(const VtkArray& a, size_t tuples, const char* what,
                     const std::vector<size_t>* rows, PointTable* t, ColumnNames* names);

// Appends <DataArray type= Name= [NumberOfComponents=] format="binary"> with base64 of
// [UInt64 byte count][raw], on a line of its own after `indent`.
void write_vtk_array(std::string* out, const char* indent, const std::string& name,
                     const char* type, size_t components, const std::string& raw);
// The beginning of the binary unstructured grid the writers write: the XML declaration,
// <VTKFile ... header_type="UInt64">, <UnstructuredGrid> and <Piece NumberOfPoints=
// NumberOfCells=>, each on a line of its own.
std::string vtk_grid_begin(size_t points, size_t cells);
// Appends the <Cells> of an unstructured grid (connectivity and offsets Int64, types UInt8,
// each raw little-endian) and closes the Piece, the grid and the file.
void write_vtk_cells_and_end(std::string* out, const std::string& connectivity,
                             const std::string& offsets, const std::string& types);
// The little-endian values of an attribute, component-interleaved, as vtk_type_name says.
std::string vtk_attribute_bytes(const PointAttribute& a, size_t n);
// Int32 for integer attributes, Float64 where any component is Float64, else Float32.
const char* vtk_type_name(const PointAttribute& a);

}  // namespace tear
