#include "tear/io/vtu.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/endian.h"
#include "tear/io/frames.h"
#include "tear/io/numbers.h"
#include "tear/io/point_groups.h"
#include "tear/io/vtk_xml.h"

namespace tear {

std::string encode_vtu(const PointTable& t) {
  const std::vector<PointAttribute> attrs = group_columns(t, AttributeFormat::Vtu);
  const auto points =
      std::find_if(attrs.begin(), attrs.end(), [](const PointAttribute& a) { return a.position; });
  if (points == attrs.end())
    throw std::runtime_error("VTU needs the position columns x, y (and z)");
  const size_t n = t.count;
  std::string out = vtk_grid_begin(n, n) + "      <PointData>\n";
  for (const PointAttribute& a : attrs)
    if (!a.position)
      write_vtk_array(&out, "        ", a.name, vtk_type_name(a), a.components.size(),
                  vtk_attribute_bytes(a, n));
  out += "      </PointData>\n      <Points>\n";
  write_vtk_array(&out, "        ", "Points", vtk_type_name(*points), 3, vtk_attribute_bytes(*points, n));
  out += "      </Points>\n";
  std::string connectivity, offsets, types(n, '\x01');  // VTK_VERTEX
  connectivity.reserve(8 * n);
  offsets.reserve(8 * n);
  for (size_t i = 0; i < n; ++i) {
    append_le<int64_t>(&connectivity, int64_t(i));
    append_le<int64_t>(&offsets, int64_t(i + 1));
  }
  write_vtk_cells_and_end(&out, connectivity, offsets, types);
  return out;
}

PointTable decode_vtu(const std::string& bytes) {
  const VtkPiece piece = read_vtk_piece(
      bytes, [](const std::string& parent) { return parent == "PointData" || parent == "Points"; });
  PointTable t;
  t.count = piece.points;
  ColumnNames columns;
  const auto p = std::find_if(piece.arrays.begin(), piece.arrays.end(),
                              [](const VtkArray& a) { return a.parent == "Points"; });
  if (p == piece.arrays.end()) throw std::runtime_error("bad VTU: no <Points> array");
  if (p->components != 3)
    throw std::runtime_error("bad VTU: the Points array has " + std::to_string(p->components) +
                             " components, not 3");
  VtkArray position = *p;
  position.name = "Points";  // whatever its Name, it is the position
  add_vtk_columns(position, piece.points, "points", nullptr, &t, &columns);
  for (const VtkArray& a : piece.arrays) {
    if (a.parent != "PointData") continue;
    if (a.name.empty()) throw std::runtime_error("bad VTU: a point array without a Name");
    add_vtk_columns(a, piece.points, "points", nullptr, &t, &columns);
  }
  return t;
}

std::string encode_pvd(const std::vector<PvdEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const PvdEntry& e : entries) {
    out += "    <DataSet timestep=\"" + shortest_text(e.time) + "\" group=\"\" part=\"0\" file=\"" +
           xml_escape(e.file) + "\"/>\n";
  }
  out +=
      "  </Collection>\n"
      "</VTKFile>\n";
  return out;
}

size_t write_frames_pvd(const std::string& dir, const std::map<int, double>& times) {
  namespace fs = std::filesystem;
  std::vector<PvdEntry> entries;
  for (const FrameFile& f : list_frames(dir, "vtu")) {
    const auto it = times.find(f.frame);
    entries.push_back({it != times.end() ? it->second : double(f.frame),
                       "frames/" + fs::path(f.path).filename().string()});
  }
  write_file_atomic((fs::path(dir) / "frames.pvd").string(), encode_pvd(entries));
  return entries.size();
}

}  // namespace tear
