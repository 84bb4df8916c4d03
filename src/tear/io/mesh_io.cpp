#include "tear/io/mesh_io.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "tear/io/atomic_file.h"
#include "tear/io/endian.h"
#include "tear/io/numbers.h"
#include "tear/io/ply_header.h"

namespace tear {

namespace {

void check_indices(const TriMesh& mesh, const char* format) {
  const int64_t n = int64_t(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int32_t i : mesh.triangles[t])
      if (i < 0 || i >= n)
        throw std::runtime_error(std::string(format) + ": triangle " + std::to_string(t) +
                                 " has vertex index " + std::to_string(i) + " of " +
                                 std::to_string(n) + " vertices");
}

// One number word of a text mesh: false unless the whole word is a number.
bool float_word(const std::string& word, float* out) {
  char* end = nullptr;
  *out = std::strtof(word.c_str(), &end);
  return !word.empty() && *end == '\0';
}

// ---- OBJ -----------------------------------------------------------------------------------

[[noreturn]] void obj_fail(size_t line, const std::string& why) {
  throw std::runtime_error("bad OBJ: line " + std::to_string(line) + ": " + why);
}

// One "i", "i/t", "i//n" or "i/t/n" face corner: the 0-based vertex index (negative indices
// count back from the last vertex read so far).
int32_t obj_corner(const std::string& word, size_t vertices, size_t line) {
  const std::string index = word.substr(0, word.find('/'));
  long long i = 0;
  const char* end = index.data() + index.size();
  const std::from_chars_result r = std::from_chars(index.data(), end, i);
  if (index.empty() || r.ec != std::errc() || r.ptr != end)
    obj_fail(line, "face corner '" + word + "' is not a vertex index");
  const long long n = (long long)vertices;
  const long long zero_based = i > 0 ? i - 1 : n + i;
  if (i == 0 || zero_based < 0 || zero_based >= n)
    obj_fail(line, "vertex index " + std::to_string(i) + " out of range (" + std::to_string(n) +
                       " vertices so far)");
  return int32_t(zero_based);
}

// ---- PLY -----------------------------------------------------------------------------------

constexpr const char* kPlyContext = "bad PLY mesh";

[[noreturn]] void ply_fail(const std::string& why) { tear::ply_fail(kPlyContext, why); }

// An integer index or count read from the file: whole and in [0, limit).
int64_t whole(double v, double limit, const PlyPlace& at, const char* what) {
  if (!(v >= 0 && v < limit) || v != std::floor(v)) {
    std::ostringstream why;
    why << at.text() << ": " << what << " " << v << ", expected an integer in [0, "
        << int64_t(limit) << ")";
    ply_fail(why.str());
  }
  return int64_t(v);
}

}  // namespace

std::string encode_obj(const TriMesh& mesh) {
  check_indices(mesh, "OBJ");
  std::string out = "# written by tear: " + std::to_string(mesh.vertices.size()) + " vertices, " +
                    std::to_string(mesh.triangles.size()) + " triangles\n";
  out.reserve(out.size() + mesh.vertices.size() * 32 + mesh.triangles.size() * 24);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    out += 'v';
    for (int a = 0; a < 3; ++a) {
      out += ' ';
      out += shortest_text(v[a]);
    }
    out += '\n';
  }
  char buf[16];
  for (const auto& t : mesh.triangles) {
    out += 'f';
    for (int32_t i : t) {
      out += ' ';
      out.append(buf, std::to_chars(buf, buf + sizeof(buf), int64_t(i) + 1).ptr);
    }
    out += '\n';
  }
  return out;
}

std::string encode_mesh_ply(const TriMesh& mesh) {
  check_indices(mesh, "PLY");
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex " +
      std::to_string(mesh.vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
      std::to_string(mesh.triangles.size()) +
      "\nproperty list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + mesh.vertices.size() * 12 + mesh.triangles.size() * 13);
  for (const Eigen::Vector3f& v : mesh.vertices)
    for (int a = 0; a < 3; ++a) append_le(&out, v[a]);
  for (const auto& t : mesh.triangles) {
    append_le(&out, uint8_t(3));
    for (int32_t i : t) append_le(&out, i);
  }
  return out;
}

TriMesh decode_obj(const std::string& text) {
  TriMesh mesh;
  std::istringstream in(text);
  std::string line;
  size_t number = 0;
  std::vector<int32_t> corners;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "v") {
      Eigen::Vector3f p;
      for (int a = 0; a < 3; ++a) {
        std::string value;
        ls >> value;
        if (!float_word(value, &p[a])) obj_fail(number, "vertex needs three numbers ('" + line + "')");
      }
      mesh.vertices.push_back(p);
    } else if (word == "f") {
      corners.clear();
      for (std::string c; ls >> c;) corners.push_back(obj_corner(c, mesh.vertices.size(), number));
      if (corners.size() < 3)
        obj_fail(number, "face with " + std::to_string(corners.size()) + " corners");
      for (size_t k = 1; k + 1 < corners.size(); ++k)
        mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
    } else if (word == "l") {
      corners.clear();
      for (std::string c; ls >> c;) corners.push_back(obj_corner(c, mesh.vertices.size(), number));
      if (corners.size() < 2)
        obj_fail(number, "line with " + std::to_string(corners.size()) + " vertex");
      for (size_t k = 0; k + 1 < corners.size(); ++k)
        mesh.segments.push_back({corners[k], corners[k + 1]});
    } else if (word.empty() || word[0] == '#' || word == "vn" || word == "vt" || word == "vp" ||
               word == "o" || word == "g" || word == "s" || word == "usemtl" || word == "mtllib" ||
               word == "p") {
      continue;
    } else {
      obj_fail(number, "unknown statement '" + word + "'");
    }
  }
  return mesh;
}

constexpr const char* kEdgeEnds[] = {"vertex1", "vertex2"};

TriMesh decode_mesh_ply(const std::string& bytes) {
  const PlyHeader h = parse_ply_header(bytes, kPlyContext);
  bool seen_vertex = false, seen_face = false, seen_edge = false, ignored_edges = false;
  for (const PlyElement& e : h.elements) {
    if (e.name == "vertex") {
      if (seen_vertex) ply_fail("two vertex elements");
      seen_vertex = true;
      for (const char* axis : {"x", "y", "z"})
        if (std::none_of(e.properties.begin(), e.properties.end(),
                         [&](const PlyProperty& p) { return p.name == axis && !p.list; }))
          ply_fail(std::string("vertex element has no scalar property '") + axis + "'");
    } else if (e.name == "face") {
      if (seen_face) ply_fail("two face elements");
      seen_face = true;
      if (std::none_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& p) {
            return p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
          }))
        ply_fail("face element has no list property 'vertex_indices'");
    } else if (e.name == "edge") {
      if (seen_edge) ply_fail("two edge elements");
      // Segments where the element names its ends (vertex1, vertex2); other edge elements
      // (a mesh's own bookkeeping) are skipped like any other element.
      seen_edge = std::all_of(std::begin(kEdgeEnds), std::end(kEdgeEnds), [&](const char* end) {
        return std::any_of(e.properties.begin(), e.properties.end(),
                           [&](const PlyProperty& p) { return p.name == end && !p.list; });
      });
      if (!seen_edge) ignored_edges = true;
    }
  }
  if (!seen_vertex) ply_fail("no vertex element");
  if (!seen_face && !seen_edge)
    ply_fail(ignored_edges ? "no face element (its edge element has no vertex1, vertex2)"
                           : "no face element (nor an edge element)");

  TriMesh mesh;
  PlyBody body(bytes, h, kPlyContext);
  std::vector<int32_t> corners;
  for (const PlyElement& e : h.elements) {
    // Rows without properties hold nothing: not read one by one, however many are declared.
    if (e.properties.empty()) continue;
    // Every row takes at least a byte (binary) or two characters (ascii): checked before
    // allocating, so a corrupt count cannot ask for terabytes.
    if (e.count > body.remaining())
      ply_fail("truncated: element '" + e.name + "' has " + std::to_string(e.count) +
               " rows, found " + std::to_string(body.remaining()) + " bytes of data");
    if (e.name == "vertex") mesh.vertices.resize(e.count);
    if (e.name == "face") mesh.triangles.reserve(e.count);
    const bool segments = e.name == "edge" && seen_edge;
    if (segments) mesh.segments.reserve(e.count);
    PlyPlace at;
    at.element = &e;
    for (size_t row = 0; row < e.count; ++row) {
      at.row = row;
      std::array<int32_t, 2> ends = {0, 0};
      for (const PlyProperty& p : e.properties) {
        at.property = &p;
        if (!p.list) {
          const double v = body.next(p.type, at);
          if (e.name == "vertex" && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
            mesh.vertices[row][p.name[0] - 'x'] = float(v);
          if (segments && (p.name == "vertex1" || p.name == "vertex2"))
            ends[p.name[6] - '1'] = int32_t(whole(v, double(mesh.vertices.size()), at, "vertex index"));
          continue;
        }
        const int64_t n = whole(body.next(p.count_type, at), 1e9, at, "list count");
        const bool indices =
            e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (indices) {
          if (n < 3)
            ply_fail("face " + std::to_string(row) + " has " + std::to_string(n) + " corners");
          corners.clear();
        }
        for (int64_t k = 0; k < n; ++k) {
          const double v = body.next(p.type, at);
          if (indices)
            corners.push_back(int32_t(whole(v, double(mesh.vertices.size()), at, "vertex index")));
        }
        if (indices)
          for (size_t k = 1; k + 1 < corners.size(); ++k)
            mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
      }
      if (segments) mesh.segments.push_back(ends);
    }
  }
  return mesh;
}

std::string encode_stl(const TriMesh& mesh) {
  check_indices(mesh, "STL");
  std::string out(80, ' ');
  out.replace(0, 15, "written by tear");
  append_le(&out, uint32_t(mesh.triangles.size()));
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f a = mesh.vertices[size_t(t[0])], b = mesh.vertices[size_t(t[1])],
                          c = mesh.vertices[size_t(t[2])];
    const Eigen::Vector3f n = (b - a).cross(c - a).normalized();
    for (const Eigen::Vector3f& v : {n, a, b, c})
      for (int k = 0; k < 3; ++k) append_le(&out, v[k]);
    append_le(&out, uint16_t(0));
  }
  return out;
}

TriMesh decode_stl(const std::string& bytes) {
  TriMesh mesh;
  // Binary when the size matches the count (some binary files also start with "solid").
  if (bytes.size() >= 84) {
    const uint32_t count = load_le<uint32_t>(bytes.data() + 80);
    if (bytes.size() == 84 + 50 * uint64_t(count)) {
      mesh.vertices.reserve(3 * size_t(count));
      for (uint32_t t = 0; t < count; ++t) {
        const char* p = bytes.data() + 84 + 50 * size_t(t) + 12;  // after the normal
        for (int k = 0; k < 3; ++k) {
          Eigen::Vector3f v;
          for (int a = 0; a < 3; ++a) v[a] = load_le<float>(p + 12 * k + 4 * a);
          mesh.vertices.push_back(v);
        }
        const int32_t i = int32_t(3 * t);
        mesh.triangles.push_back({i, i + 1, i + 2});
      }
      return mesh;
    }
  }
  std::istringstream in(bytes);
  std::string word;
  if (!(in >> word) || word != "solid")
    throw std::runtime_error("bad STL: neither binary (" + std::to_string(bytes.size()) +
                             " bytes do not match its triangle count) nor ascii (no 'solid')");
  // Ascii: only "vertex x y z" lines carry data; every third vertex closes a triangle.
  size_t vertex_lines = 0;
  while (in >> word) {
    if (word == "endsolid") break;
    if (word != "vertex") continue;
    Eigen::Vector3f v;
    for (int a = 0; a < 3; ++a) {
      std::string value;
      in >> value;
      if (!float_word(value, &v[a]))
        throw std::runtime_error("bad STL: vertex " + std::to_string(vertex_lines) +
                                 " needs three numbers, got '" + value + "'");
    }
    mesh.vertices.push_back(v);
    if (++vertex_lines % 3 == 0) {
      const int32_t i = int32_t(vertex_lines - 3);
      mesh.triangles.push_back({i, i + 1, i + 2});
    }
  }
  if (vertex_lines % 3 != 0)
    throw std::runtime_error("bad STL: " + std::to_string(vertex_lines) +
                             " vertices, not a whole number of triangles");
  return mesh;
}

TriMesh read_mesh_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply" && ext != ".stl")
    throw std::runtime_error("'" + path + "': unknown mesh format '" + ext +
                             "' (expected .obj, .ply or .stl)");
  const std::string bytes = read_file(path);
  try {
    if (ext == ".obj") return decode_obj(bytes);
    if (ext == ".ply") return decode_mesh_ply(bytes);
    return decode_stl(bytes);
  } catch (const std::exception& e) {
    throw std::runtime_error("'" + path + "': " + e.what());
  }
}

}  // namespace tear
