#include "tear/io/mesh_frames.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "tear/io/endian.h"
#include "tear/io/atomic_file.h"
#include "tear/io/numbers.h"
#include "tear/io/ply_header.h"
#include "tear/io/vtu.h"

namespace tear {

namespace {

constexpr const char* kContext = "bad PLY mesh part";

const char* ply_type(ColumnType t) {
  switch (t) {
    case ColumnType::Int32: return "int";
    case ColumnType::UInt8: return "uchar";
    case ColumnType::Float32: return "float";
    case ColumnType::Float64: return "double";
  }
  return "?";
}

void put(std::string* out, ColumnType t, double v) {
  char b[8];
  switch (t) {
    case ColumnType::Int32: store_le(b, int32_t(v)), out->append(b, 4); break;
    case ColumnType::UInt8: store_le(b, uint8_t(v)), out->append(b, 1); break;
    case ColumnType::Float32: store_le(b, float(v)), out->append(b, 4); break;
    case ColumnType::Float64: store_le(b, v), out->append(b, 8); break;
  }
}

std::string properties(const PointTable& t) {
  std::string h;
  for (size_t c = 0; c < t.names.size(); ++c)
    h += "property " + std::string(ply_type(t.types[c])) + " " + t.names[c] + "\n";
  return h;
}

ColumnType column_type(NumberType t) {
  switch (t) {
    case NumberType::Int32: return ColumnType::Int32;
    case NumberType::UInt8: return ColumnType::UInt8;
    case NumberType::Float32: return ColumnType::Float32;
    default: return ColumnType::Float64;
  }
}

}  // namespace

const std::vector<std::string>& mesh_part_formats() {
  static const std::vector<std::string> kFormats = {"ply", "obj", "vtu", "geo"};
  return kFormats;
}

std::string encode_mesh_part(const MeshPart& part, const std::string& format) {
  if (part.corners == 4 && format != "vtu")
    throw std::runtime_error("mesh part '" + part.name + "' is a volume (tetrahedra), written as "
                             "vtu only, not '" + format + "'");
  if (format == "ply") return encode_mesh_part_ply(part);
  if (format == "obj") return encode_mesh_part_obj(part);
  if (format == "vtu") return encode_mesh_part_vtu(part);
  if (format == "geo") return encode_mesh_part_geo(part);
  throw std::runtime_error("mesh parts are written as ply, obj, vtu or geo, not '" + format + "'");
}

std::vector<std::string> mesh_part_formats_of(const MeshPart& part,
                                              const std::vector<std::string>& requested) {
  if (part.corners == 4) return {"vtu"};
  return requested;
}

namespace {

// The vertex's position and the part's connectivity checked once for every encoder.
void check_part(const MeshPart& part) {
  part.vertices.check_shape();
  part.element_columns.check_shape();
  if (part.element_columns.count != part.elements.size())
    throw std::runtime_error("mesh part '" + part.name + "': " +
                             std::to_string(part.element_columns.count) + " element rows for " +
                             std::to_string(part.elements.size()) + " elements");
  for (size_t k = 0; k < part.elements.size(); ++k)
    for (int c = 0; c < part.corners; ++c)
      if (part.elements[k][size_t(c)] >= part.vertices.count)
        throw std::runtime_error("mesh part '" + part.name + "': element " + std::to_string(k) +
                                 " uses vertex " + std::to_string(part.elements[k][size_t(c)]) +
                                 " of " + std::to_string(part.vertices.count));
}

}  // namespace

std::string encode_mesh_part_obj(const MeshPart& part) {
  check_part(part);
  const std::vector<Eigen::Vector3d> x = positions(part.vertices);
  std::string out = "# written by tear: " + part.name + ", " + std::to_string(x.size()) +
                    " vertices, " + std::to_string(part.elements.size()) +
                    (part.corners == 3 ? " triangles\n" : " segments\n");
  for (const Eigen::Vector3d& p : x)
    out += "v " + shortest_text(float(p.x())) + " " + shortest_text(float(p.y())) + " " +
           shortest_text(float(p.z())) + "\n";
  for (const auto& e : part.elements) {
    out += part.corners == 3 ? "f" : "l";
    for (int c = 0; c < part.corners; ++c) out += " " + std::to_string(e[size_t(c)] + 1);
    out += "\n";
  }
  return out;
}

std::string encode_mesh_part_geo(const MeshPart& part) {
  check_part(part);
  const PointTable& v = part.vertices;
  const PointTable& e = part.element_columns;
  const std::vector<Eigen::Vector3d> x = positions(v);
  // One attribute per column (vx vy vz as the vector v); int for the integer columns.
  struct Attribute {
    std::string name;
    std::vector<const std::vector<double>*> values;
    bool integer;
  };
  auto attributes_of = [](const PointTable& t, bool points) {
    std::vector<Attribute> out;
    for (size_t c = 0; c < t.names.size(); ++c) {
      const std::string& n = t.names[c];
      if (points && (n == "x" || n == "y" || n == "z" || n == "vy" || n == "vz")) continue;
      const bool integer = t.types[c] == ColumnType::Int32 || t.types[c] == ColumnType::UInt8;
      if (points && n == "vx")
        out.push_back({"v",
                       {&t.columns[c], t.has("vy") ? &t.column("vy") : nullptr,
                        t.has("vz") ? &t.column("vz") : nullptr},
                       false});
      else
        out.push_back({n, {&t.columns[c]}, integer});
    }
    return out;
  };
  const std::vector<Attribute> pa = attributes_of(v, true), ea = attributes_of(e, false);
  auto header = [](const std::vector<Attribute>& a) {
    std::string h;
    for (const Attribute& at : a) {
      h += at.name + " " + std::to_string(at.values.size()) + (at.integer ? " int" : " float");
      for (size_t k = 0; k < at.values.size(); ++k) h += " 0";
      h += "\n";
    }
    return h;
  };
  auto values = [](const std::vector<Attribute>& a, size_t row) {
    std::string out;
    for (const Attribute& at : a)
      for (const std::vector<double>* c : at.values) {
        const double value = c ? (*c)[row] : 0.0;
        out += (out.empty() ? "" : " ") + (at.integer ? std::to_string(int64_t(value))
                                                       : shortest_text(float(value)));
      }
    return out;
  };
  std::string out = "PGEOMETRY V5\nNPoints " + std::to_string(x.size()) + " NPrims " +
                    std::to_string(part.elements.size()) +
                    "\nNPointGroups 0 NPrimGroups 0\nNPointAttrib " + std::to_string(pa.size()) +
                    " NVertexAttrib 0 NPrimAttrib " + std::to_string(ea.size()) + " NAttrib 0\n";
  if (!pa.empty()) out += "PointAttrib\n" + header(pa);
  for (size_t i = 0; i < x.size(); ++i) {
    out += shortest_text(float(x[i].x())) + " " + shortest_text(float(x[i].y())) + " " +
           shortest_text(float(x[i].z())) + " 1";
    if (!pa.empty()) out += " (" + values(pa, i) + ")";
    out += "\n";
  }
  if (!ea.empty() && !part.elements.empty()) out += "PrimitiveAttrib\n" + header(ea);
  if (!part.elements.empty()) out += "Run " + std::to_string(part.elements.size()) + " Poly\n";
  // Triangles are closed polygons ("<"), segments open ones (":").
  const char* closed = part.corners == 3 ? " < " : " : ";
  for (size_t k = 0; k < part.elements.size(); ++k) {
    out += std::to_string(part.corners) + closed;
    for (int c = 0; c < part.corners; ++c)
      out += (c ? " " : "") + std::to_string(part.elements[k][size_t(c)]);
    if (!ea.empty()) out += " [" + values(ea, k) + "]";
    out += "\n";
  }
  out += "beginExtra\nendExtra\n";
  return out;
}

std::string encode_mesh_part_vtu(const MeshPart& part) {
  check_part(part);
  const PointTable& v = part.vertices;
  const PointTable& e = part.element_columns;
  const std::vector<Eigen::Vector3d> x = positions(v);
  auto type_of = [](ColumnType t) {
    return t == ColumnType::Int32 ? "Int32" : t == ColumnType::UInt8 ? "UInt8"
                                  : t == ColumnType::Float64         ? "Float64"
                                                                     : "Float32";
  };
  auto values = [](const std::vector<double>& c, bool integer) {
    std::string s;
    for (double d : c) s += (integer ? std::to_string(int64_t(d)) : shortest_text(float(d))) + " ";
    return s;
  };
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" +
      std::to_string(v.count) + "\" NumberOfCells=\"" + std::to_string(part.elements.size()) +
      "\">\n      <Points>\n        <DataArray type=\"Float32\" NumberOfComponents=\"3\" "
      "format=\"ascii\">";
  for (const Eigen::Vector3d& p : x)
    out += shortest_text(float(p.x())) + " " + shortest_text(float(p.y())) + " " +
           shortest_text(float(p.z())) + " ";
  out += "</DataArray>\n      </Points>\n      <PointData>\n";
  const bool velocity = v.has("vx") && v.has("vy");
  if (velocity) {
    out += "        <DataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\" "
           "format=\"ascii\">";
    for (size_t i = 0; i < v.count; ++i)
      out += shortest_text(float(v.column("vx")[i])) + " " + shortest_text(float(v.column("vy")[i])) +
             " " + shortest_text(float(v.has("vz") ? v.column("vz")[i] : 0.0)) + " ";
    out += "</DataArray>\n";
  }
  for (size_t c = 0; c < v.names.size(); ++c) {
    const std::string& n = v.names[c];
    if (n == "x" || n == "y" || n == "z" || (velocity && (n == "vx" || n == "vy" || n == "vz")))
      continue;
    const bool integer = v.types[c] == ColumnType::Int32 || v.types[c] == ColumnType::UInt8;
    out += "        <DataArray type=\"" + std::string(type_of(v.types[c])) + "\" Name=\"" + n +
           "\" format=\"ascii\">" + values(v.columns[c], integer) + "</DataArray>\n";
  }
  out += "      </PointData>\n      <CellData>\n";
  const bool fiber = e.has("fx") && e.has("fy") && e.has("fz");
  if (fiber) {
    out += "        <DataArray type=\"Float32\" Name=\"fiber\" NumberOfComponents=\"3\" "
           "format=\"ascii\">";
    for (size_t i = 0; i < e.count; ++i)
      out += shortest_text(float(e.column("fx")[i])) + " " + shortest_text(float(e.column("fy")[i])) +
             " " + shortest_text(float(e.column("fz")[i])) + " ";
    out += "</DataArray>\n";
  }
  for (size_t c = 0; c < e.names.size(); ++c) {
    if (fiber && (e.names[c] == "fx" || e.names[c] == "fy" || e.names[c] == "fz")) continue;
    const bool integer = e.types[c] == ColumnType::Int32 || e.types[c] == ColumnType::UInt8;
    out += "        <DataArray type=\"" + std::string(type_of(e.types[c])) + "\" Name=\"" +
           e.names[c] + "\" format=\"ascii\">" + values(e.columns[c], integer) + "</DataArray>\n";
  }
  out += "      </CellData>\n      <Cells>\n        <DataArray type=\"Int32\" Name=\"connectivity\" "
         "format=\"ascii\">";
  for (const auto& el : part.elements)
    for (int c = 0; c < part.corners; ++c) out += std::to_string(el[size_t(c)]) + " ";
  out += "</DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">";
  for (size_t k = 1; k <= part.elements.size(); ++k) out += std::to_string(k * size_t(part.corners)) + " ";
  out += "</DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">";
  const char* cell = part.corners == 4 ? "10 " : part.corners == 3 ? "5 " : "3 ";  // VTK_TETRA,
                                                                             // _TRIANGLE, _LINE
  for (size_t k = 0; k < part.elements.size(); ++k) out += cell;
  out += "</DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

void write_mesh_part_pvd(const std::string& dir, const std::string& part,
                         const std::map<int, double>& times) {
  std::vector<PvdEntry> entries;
  for (const auto& [frame, time] : times) {
    char name[48];
    std::snprintf(name, sizeof name, "frames/%05d.", frame);
    entries.push_back({time, name + part + ".vtu"});
  }
  write_file_atomic((std::filesystem::path(dir) / (part + ".pvd")).string(), encode_pvd(entries));
}

std::string mesh_part_path(const std::string& dir, int frame, const std::string& part,
                           const std::string& format) {
  char name[32];
  std::snprintf(name, sizeof(name), "%05d.", frame);
  return (std::filesystem::path(dir) / "frames" / (name + part + "." + format)).string();
}

std::string encode_mesh_part_ply(const MeshPart& part) {
  check_part(part);
  const bool faces = part.corners == 3;
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by tear: " +
                    part.name + "\nelement vertex " + std::to_string(part.vertices.count) +
                    "\n" + properties(part.vertices);
  out += std::string("element ") + (faces ? "face " : "edge ") +
         std::to_string(part.elements.size()) + "\n";
  out += faces ? "property list uchar int vertex_indices\n"
               : "property int vertex1\nproperty int vertex2\n";
  out += properties(part.element_columns) + "end_header\n";
  const PointTable& v = part.vertices;
  for (size_t i = 0; i < v.count; ++i)
    for (size_t c = 0; c < v.names.size(); ++c) put(&out, v.types[c], v.columns[c][i]);
  const PointTable& e = part.element_columns;
  for (size_t k = 0; k < part.elements.size(); ++k) {
    if (faces) out.push_back(char(3));
    for (int c = 0; c < part.corners; ++c)
      put(&out, ColumnType::Int32, double(part.elements[k][size_t(c)]));
    for (size_t c = 0; c < e.names.size(); ++c) put(&out, e.types[c], e.columns[c][k]);
  }
  return out;
}

MeshPart decode_mesh_part_ply(const std::string& bytes) {
  const PlyHeader h = parse_ply_header(bytes, kContext);
  if (h.elements.size() != 2 || h.elements[0].name != "vertex" ||
      (h.elements[1].name != "face" && h.elements[1].name != "edge"))
    ply_fail(kContext, "expected a vertex element, then a face or an edge element");
  MeshPart part;
  part.corners = h.elements[1].name == "face" ? 3 : 2;
  PlyBody body(bytes, h, kContext);
  for (int which = 0; which < 2; ++which) {
    const PlyElement& el = h.elements[size_t(which)];
    PointTable& t = which == 0 ? part.vertices : part.element_columns;
    std::vector<int> column_of(el.properties.size(), -1);
    for (size_t p = 0; p < el.properties.size(); ++p) {
      const PlyProperty& prop = el.properties[p];
      if (prop.list || prop.name == "vertex1" || prop.name == "vertex2") continue;
      column_of[p] = int(t.names.size());
      t.names.push_back(prop.name);
      t.types.push_back(column_type(prop.type));
      t.columns.emplace_back();
    }
    t.count = el.count;
    if (which == 1) part.elements.assign(el.count, {0, 0, 0});
    PlyPlace at;
    at.element = &el;
    for (size_t row = 0; row < el.count; ++row) {
      at.row = row;
      for (size_t p = 0; p < el.properties.size(); ++p) {
        const PlyProperty& prop = el.properties[p];
        at.property = &prop;
        if (prop.list) {
          const double n = body.next(prop.count_type, at);
          if (n != 3) ply_fail(kContext, "face " + std::to_string(row) + " is not a triangle");
          for (int c = 0; c < 3; ++c) {
            const double i = body.next(prop.type, at);
            if (!(i >= 0 && i < double(part.vertices.count)))
              ply_fail(kContext, "face " + std::to_string(row) + " has a vertex index out of range (" +
                                     std::to_string(part.vertices.count) + " vertices)");
            part.elements[row][size_t(c)] = uint32_t(i);
          }
          continue;
        }
        const double value = body.next(prop.type, at);
        if ((prop.name == "vertex1" || prop.name == "vertex2") && !(value >= 0 && value < double(part.vertices.count)))
          ply_fail(kContext, "edge " + std::to_string(row) + " has a vertex index out of range (" +
                                 std::to_string(part.vertices.count) + " vertices)");
        if (prop.name == "vertex1" || prop.name == "vertex2")
          part.elements[row][size_t(prop.name[6] - '1')] = uint32_t(value);
        else
          t.columns[size_t(column_of[p])].push_back(value);
      }
    }
  }
  return part;
}

const std::vector<std::string>& mesh_part_names() {
  static const std::vector<std::string> names{"curves", "surfaces", "fem"};
  return names;
}

std::vector<MeshPart> read_mesh_parts(const std::string& dir, int frame) {
  namespace fs = std::filesystem;
  std::vector<MeshPart> parts;
  for (const std::string& name : mesh_part_names()) {
    const std::string ply = mesh_part_path(dir, frame, name, "ply");
    if (!fs::exists(ply)) {
      for (const std::string& f : mesh_part_formats())
        if (f != "ply" && fs::exists(mesh_part_path(dir, frame, name, f)))
          throw std::runtime_error(mesh_part_path(dir, frame, name, f) +
                                   ": the run wrote this mesh part without its PLY file, which "
                                   "tear reads mesh parts from (keep \"ply\" in the scene's "
                                   "output.mesh_formats, its default)");
      continue;
    }
    try {
      parts.push_back(decode_mesh_part_ply(read_file(ply)));
    } catch (const std::exception& e) {
      throw std::runtime_error(ply + ": " + e.what());
    }
    parts.back().name = name;
  }
  return parts;
}

}  // namespace tear
