#include "tear/io/ply.h"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace tear {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "PLY encoding assumes a little-endian host");

void PlyTable::add(const std::string& name, PlyType type, std::vector<double> values) {
  if (values.size() != count)
    throw std::runtime_error("PLY column '" + name + "' has " + std::to_string(values.size()) +
                             " values, the table " + std::to_string(count));
  if (has(name)) throw std::runtime_error("PLY column '" + name + "' added twice");
  names.push_back(name);
  types.push_back(type);
  columns.push_back(std::move(values));
}

bool PlyTable::has(const std::string& name) const {
  for (const std::string& n : names)
    if (n == name) return true;
  return false;
}

const std::vector<double>& PlyTable::column(const std::string& name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return columns[i];
  throw std::runtime_error("PLY has no column '" + name + "'");
}

namespace {

struct TypeInfo {
  const char* name;
  int size;
};

TypeInfo info(PlyType t) {
  switch (t) {
    case PlyType::Int32: return {"int", 4};
    case PlyType::UInt8: return {"uchar", 1};
    case PlyType::Float32: return {"float", 4};
    case PlyType::Float64: return {"double", 8};
  }
  return {"?", 0};
}

// Every scalar type name of the PLY format, with its size and how to read it.
enum class Scalar { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parse_scalar(const std::string& name, Scalar* s, int* size) {
  static const struct {
    const char* a;
    const char* b;
    Scalar s;
    int size;
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

template <class T>
double load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return double(v);
}

double read_scalar(Scalar s, const char* p) {
  switch (s) {
    case Scalar::I8: return load<int8_t>(p);
    case Scalar::U8: return load<uint8_t>(p);
    case Scalar::I16: return load<int16_t>(p);
    case Scalar::U16: return load<uint16_t>(p);
    case Scalar::I32: return load<int32_t>(p);
    case Scalar::U32: return load<uint32_t>(p);
    case Scalar::F32: return load<float>(p);
    case Scalar::F64: return load<double>(p);
  }
  return 0;
}

PlyType table_type(Scalar s) {
  switch (s) {
    case Scalar::U8: return PlyType::UInt8;
    case Scalar::F32: return PlyType::Float32;
    case Scalar::F64: return PlyType::Float64;
    default: return PlyType::Int32;
  }
}

}  // namespace

std::string encode_ply(const PlyTable& t) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex "
    << t.count << "\n";
  size_t row = 0;
  for (size_t c = 0; c < t.names.size(); ++c) {
    h << "property " << info(t.types[c]).name << " " << t.names[c] << "\n";
    row += size_t(info(t.types[c]).size);
  }
  h << "end_header\n";
  std::string out = h.str();
  const size_t header = out.size();
  out.resize(header + row * t.count);
  char* p = &out[header];
  for (size_t i = 0; i < t.count; ++i) {
    for (size_t c = 0; c < t.names.size(); ++c) {
      const double v = t.columns[c][i];
      switch (t.types[c]) {
        case PlyType::Int32: {
          const int32_t x = int32_t(v);
          std::memcpy(p, &x, 4);
          p += 4;
          break;
        }
        case PlyType::UInt8: {
          const uint8_t x = uint8_t(v);
          *p++ = char(x);
          break;
        }
        case PlyType::Float32: {
          const float x = float(v);
          std::memcpy(p, &x, 4);
          p += 4;
          break;
        }
        case PlyType::Float64: {
          std::memcpy(p, &v, 8);
          p += 8;
          break;
        }
      }
    }
  }
  return out;
}

PlyTable decode_ply(const std::string& bytes) {
  auto fail = [](const std::string& why) { throw std::runtime_error("bad PLY: " + why); };
  const size_t end = bytes.find("end_header");
  if (bytes.compare(0, 3, "ply") != 0) fail("does not start with 'ply'");
  if (end == std::string::npos) fail("no end_header");
  size_t data = bytes.find('\n', end);
  if (data == std::string::npos) fail("no line break after end_header");
  ++data;
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  PlyTable t;
  std::vector<Scalar> scalars;
  std::vector<int> sizes;
  bool in_vertex = false, seen_vertex = false;
  while (std::getline(header, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (word == "element") {
      std::string name;
      long long n = -1;
      ls >> name >> n;
      if (n < 0) fail("element '" + name + "' without a count");
      in_vertex = name == "vertex";
      if (in_vertex) {
        if (seen_vertex) fail("two vertex elements");
        seen_vertex = true;
        t.count = size_t(n);
      } else if (n != 0) {
        fail("element '" + name + "' has data; only 'vertex' is supported");
      }
    } else if (word == "property") {
      std::string type, name;
      ls >> type >> name;
      if (!in_vertex) continue;  // properties of empty elements (e.g. "face 0")
      if (type == "list") fail("list properties are not supported");
      Scalar s;
      int size;
      if (!parse_scalar(type, &s, &size)) fail("unknown property type '" + type + "'");
      t.names.push_back(name);
      t.types.push_back(table_type(s));
      scalars.push_back(s);
      sizes.push_back(size);
    }
  }
  if (!seen_vertex) fail("no vertex element");
  t.columns.assign(t.names.size(), std::vector<double>(t.count));
  if (format == "binary_little_endian") {
    size_t row = 0;
    for (int s : sizes) row += size_t(s);
    if (bytes.size() - data < row * t.count)
      fail("truncated: " + std::to_string(t.count) + " vertices need " +
           std::to_string(row * t.count) + " bytes, found " + std::to_string(bytes.size() - data));
    const char* p = bytes.data() + data;
    for (size_t i = 0; i < t.count; ++i)
      for (size_t c = 0; c < scalars.size(); ++c) {
        t.columns[c][i] = read_scalar(scalars[c], p);
        p += sizes[c];
      }
  } else if (format == "ascii") {
    std::istringstream body(bytes.substr(data));
    for (size_t i = 0; i < t.count; ++i)
      for (size_t c = 0; c < scalars.size(); ++c)
        if (!(body >> t.columns[c][i]))
          fail("truncated or non-numeric ascii data at vertex " + std::to_string(i));
  } else {
    fail("unsupported format '" + format + "'");
  }
  return t;
}

}  // namespace tear
