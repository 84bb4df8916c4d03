#include "tear/io/ply.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace tear {

namespace {

// The files are little-endian whatever the host; on a little-endian host these compile to
// plain loads and stores.
constexpr bool kHostLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;

template <class T>
void store_le(char* p, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (!kHostLittleEndian) std::reverse(b, b + sizeof(T));
  std::memcpy(p, b, sizeof(T));
}

template <class T>
double load_le(const char* p) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if constexpr (!kHostLittleEndian) std::reverse(b, b + sizeof(T));
  T value;
  std::memcpy(&value, b, sizeof(T));
  return double(value);
}

struct TypeInfo {
  const char* name;
  size_t size;
};

TypeInfo info(ColumnType t) {
  switch (t) {
    case ColumnType::Int32: return {"int", 4};
    case ColumnType::UInt8: return {"uchar", 1};
    case ColumnType::Float32: return {"float", 4};
    case ColumnType::Float64: return {"double", 8};
  }
  return {"?", 0};
}

// Every scalar type of the PLY format, under its old and its sized name.
enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parse_scalar(const std::string& name, Scalar* s, size_t* size) {
  static const struct {
    const char* a;
    const char* b;
    Scalar s;
    size_t size;
  } kTypes[] = {{"char", "int8", Scalar::I8, 1},      {"uchar", "uint8", Scalar::U8, 1},
                {"short", "int16", Scalar::I16, 2},   {"ushort", "uint16", Scalar::U16, 2},
                {"int", "int32", Scalar::I32, 4},     {"uint", "uint32", Scalar::U32, 4},
                {"float", "float32", Scalar::F32, 4}, {"double", "float64", Scalar::F64, 8}};
  for (const auto& t : kTypes) {
    if (name == t.a || name == t.b) {
      *s = t.s;
      *size = t.size;
      return true;
    }
  }
  return false;
}

double read_scalar(Scalar s, const char* p) {
  switch (s) {
    case Scalar::I8: return load_le<int8_t>(p);
    case Scalar::U8: return load_le<uint8_t>(p);
    case Scalar::I16: return load_le<int16_t>(p);
    case Scalar::U16: return load_le<uint16_t>(p);
    case Scalar::I32: return load_le<int32_t>(p);
    case Scalar::U32: return load_le<uint32_t>(p);
    case Scalar::F32: return load_le<float>(p);
    case Scalar::F64: return load_le<double>(p);
  }
  return 0;
}

// The nearest ColumnType that holds every value of `s` exactly (uint32 and the 8/16-bit signed
// types do not fit uchar, so they become int32, and uint32 beyond 2^31 becomes double).
ColumnType table_type(Scalar s) {
  switch (s) {
    case Scalar::U8: return ColumnType::UInt8;
    case Scalar::U32: return ColumnType::Float64;
    case Scalar::F32: return ColumnType::Float32;
    case Scalar::F64: return ColumnType::Float64;
    default: return ColumnType::Int32;
  }
}

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error("bad PLY: " + why); }

// A non-negative decimal count, all digits, no sign, no overflow.
bool parse_count(const std::string& word, size_t* n) {
  if (word.empty() || word.size() > 19) return false;
  for (char c : word)
    if (c < '0' || c > '9') return false;
  *n = size_t(std::strtoull(word.c_str(), nullptr, 10));
  return true;
}

}  // namespace

std::string encode_ply(const PointTable& t) {
  if (t.types.size() != t.names.size() || t.columns.size() != t.names.size())
    throw std::runtime_error("PLY table has " + std::to_string(t.names.size()) + " names, " +
                             std::to_string(t.types.size()) + " types and " +
                             std::to_string(t.columns.size()) + " columns");
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex " +
      std::to_string(t.count) + "\n";
  size_t row = 0;
  for (size_t c = 0; c < t.names.size(); ++c) {
    if (t.columns[c].size() != t.count)
      throw std::runtime_error("PLY column '" + t.names[c] + "' has " +
                               std::to_string(t.columns[c].size()) + " values, the table " +
                               std::to_string(t.count));
    out += "property " + std::string(info(t.types[c]).name) + " " + t.names[c] + "\n";
    row += info(t.types[c]).size;
  }
  out += "end_header\n";
  const size_t header = out.size();
  out.resize(header + row * t.count);
  // Vertex-major: row i holds every column's value i. Values must fit the column's type.
  char* p = &out[header];
  for (size_t i = 0; i < t.count; ++i) {
    for (size_t c = 0; c < t.names.size(); ++c) {
      const double v = t.columns[c][i];
      switch (t.types[c]) {
        case ColumnType::Int32: store_le(p, int32_t(v)), p += 4; break;
        case ColumnType::UInt8: store_le(p, uint8_t(v)), p += 1; break;
        case ColumnType::Float32: store_le(p, float(v)), p += 4; break;
        case ColumnType::Float64: store_le(p, v), p += 8; break;
      }
    }
  }
  return out;
}

PointTable decode_ply(const std::string& bytes) {
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0)
    fail("does not start with 'ply'");
  size_t pos = bytes.find('\n') + 1;

  PointTable t;
  std::string format;
  std::vector<Scalar> scalars;
  std::vector<size_t> sizes;
  bool any_element = false, in_vertex = false, seen_vertex = false, ended = false;
  while (!ended && pos < bytes.size()) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word.empty() || word == "comment" || word == "obj_info") continue;
    if (word == "end_header") {
      if (eol == bytes.size()) fail("no line break after end_header");
      ended = true;
    } else if (word == "format") {
      if (!format.empty()) fail("two format lines");
      ls >> format;
      if (format.empty()) fail("format line without a format");
    } else if (word == "element") {
      std::string name, count;
      size_t n = 0;
      ls >> name >> count;
      if (!parse_count(count, &n)) fail("element '" + name + "' without a valid count");
      any_element = true;
      in_vertex = name == "vertex";
      if (in_vertex) {
        if (seen_vertex) fail("two vertex elements");
        seen_vertex = true;
        t.count = n;
      } else if (n != 0) {
        fail("element '" + name + "' has data; only 'vertex' is supported");
      }
    } else if (word == "property") {
      std::string type, name;
      ls >> type >> name;
      if (!any_element) fail("property before any element");
      if (!in_vertex) continue;  // properties of an empty element (e.g. "face 0")
      if (type == "list") fail("list properties are not supported ('" + line + "')");
      Scalar s;
      size_t size;
      if (!parse_scalar(type, &s, &size)) fail("unknown property type '" + type + "'");
      if (name.empty()) fail("property without a name ('" + line + "')");
      if (t.has(name)) fail("property '" + name + "' appears twice");
      t.names.push_back(name);
      t.types.push_back(table_type(s));
      scalars.push_back(s);
      sizes.push_back(size);
    } else {
      fail("unexpected header line '" + line + "'");
    }
  }
  if (!ended) fail("no end_header line");
  if (format.empty()) fail("no format line");
  if (!seen_vertex) fail("no vertex element");

  const size_t available = bytes.size() - pos;
  const size_t cols = scalars.size();
  if (format == "binary_little_endian") {
    size_t row = 0;
    for (size_t s : sizes) row += s;
    // Checked before allocating, so a corrupt count cannot ask for terabytes.
    if (row > 0 && t.count > available / row)
      fail("truncated: " + std::to_string(t.count) + " vertices of " + std::to_string(row) +
           " bytes, found " + std::to_string(available) + " bytes of data");
    t.columns.assign(cols, std::vector<double>(t.count));
    const char* p = bytes.data() + pos;
    for (size_t i = 0; i < t.count; ++i)
      for (size_t c = 0; c < cols; ++c) {
        t.columns[c][i] = read_scalar(scalars[c], p);
        p += sizes[c];
      }
  } else if (format == "ascii") {
    // Every value takes at least one character and a separator.
    if (cols > 0 && t.count > (available + 1) / 2 / cols)
      fail("truncated: " + std::to_string(t.count) + " vertices of " + std::to_string(cols) +
           " values cannot fit in " + std::to_string(available) + " bytes of data");
    t.columns.assign(cols, std::vector<double>(t.count));
    const char* p = bytes.c_str() + pos;
    for (size_t i = 0; i < t.count; ++i)
      for (size_t c = 0; c < cols; ++c) {
        char* end = nullptr;
        t.columns[c][i] = std::strtod(p, &end);
        if (end == p || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))))
          fail("truncated or non-numeric ascii data at vertex " + std::to_string(i) +
               ", property '" + t.names[c] + "'");
        p = end;
      }
  } else {
    fail("unsupported format '" + format + "' (binary_little_endian and ascii are read)");
  }
  return t;
}

}  // namespace tear
