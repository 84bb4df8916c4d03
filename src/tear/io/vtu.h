// io/: VTK XML unstructured grids (.vtu, what ParaView opens) of points, one VTK_VERTEX cell
// per point, with point arrays grouped by io/point_groups.h; and the ParaView collection
// (.pvd) that makes a run's VTU frames one time series.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

// <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian"
// header_type="UInt64">, one Piece of N points and N cells; every DataArray is
// format="binary": base64 of [UInt64 byte count][little-endian values]. Points from x y z
// (z = 0 where absent); cells: connectivity 0..N-1 and offsets 1..N (Int64), types 1 (UInt8).
// Point arrays: "velocity" (vx vy vz) and "fiber" (fx fy fz) of 3 components, every other
// column under its own name; Int32 for Int32/UInt8 columns, Float64 for Float64 columns,
// Float32 otherwise.
std::string encode_vtu(const PointTable& table);

// A strict reader of single-piece unstructured grids as encode_vtu writes them (binary with a
// UInt32 or UInt64 header, or ascii; no compression, no appended data). Columns: x y z, then
// each point array in file order, named by attribute_columns(); integer arrays become Int32
// columns (UInt8 stays UInt8), Float32/Float64 stay as they are, so encode then decode gives
// the same columns and values with UInt8 as Int32. Throws std::runtime_error with the reason.
PointTable decode_vtu(const std::string& bytes);

// One dataset of a ParaView collection: its time and its path relative to the .pvd file.
struct PvdEntry {
  double time = 0;
  std::string file;
};
// <VTKFile type="Collection" version="0.1">, one <DataSet timestep= file=/> per entry.
std::string encode_pvd(const std::vector<PvdEntry>& entries);

// Writes DIR/frames.pvd (atomically) listing every DIR/frames/NNNNN.vtu in frame order with
// timestep times[frame], or the frame number for a frame `times` does not have. Returns the
// number of datasets listed.
size_t write_frames_pvd(const std::string& dir, const std::map<int, double>& times);

}  // namespace tear
