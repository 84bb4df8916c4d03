#include "tear/io/ply_header.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tear {

namespace {

// PLY's scalar types, under their old and their sized names.
const struct {
  const char* old_name;
  const char* sized_name;
  NumberType type;
} kTypes[] = {
    {"char", "int8", NumberType::Int8},        {"uchar", "uint8", NumberType::UInt8},
    {"short", "int16", NumberType::Int16},     {"ushort", "uint16", NumberType::UInt16},
    {"int", "int32", NumberType::Int32},       {"uint", "uint32", NumberType::UInt32},
    {"float", "float32", NumberType::Float32}, {"double", "float64", NumberType::Float64}};

bool parse_type(const std::string& name, NumberType* type) {
  for (const auto& t : kTypes)
    if (name == t.old_name || name == t.sized_name) {
      *type = t.type;
      return true;
    }
  return false;
}

// The sized name of a PLY scalar type.
const char* type_name(NumberType type) {
  for (const auto& t : kTypes)
    if (t.type == type) return t.sized_name;
  return "?";
}

}  // namespace

void ply_fail(const char* context, const std::string& why) {
  throw std::runtime_error(std::string(context) + ": " + why);
}

PlyHeader parse_ply_header(const std::string& bytes, const char* context) {
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0)
    ply_fail(context, "does not start with 'ply'");
  PlyHeader h;
  std::string format;
  size_t pos = bytes.find('\n') + 1;
  bool ended = false;
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
      if (eol == bytes.size()) ply_fail(context, "no line break after end_header");
      ended = true;
    } else if (word == "format") {
      if (!format.empty()) ply_fail(context, "two format lines");
      ls >> format;
      if (format.empty()) ply_fail(context, "format line without a format");
    } else if (word == "element") {
      PlyElement e;
      std::string count;
      ls >> e.name >> count;
      if (!parse_count(count, &e.count))
        ply_fail(context, "element '" + e.name + "' without a valid count");
      h.elements.push_back(e);
    } else if (word == "property") {
      if (h.elements.empty()) ply_fail(context, "property before any element");
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_type;
        p.list = true;
        ls >> count_type >> type;
        if (!parse_type(count_type, &p.count_type))
          ply_fail(context, "unknown list count type '" + count_type + "'");
      }
      if (!parse_type(type, &p.type)) ply_fail(context, "unknown property type '" + type + "'");
      ls >> p.name;
      if (p.name.empty()) ply_fail(context, "property without a name ('" + line + "')");
      h.elements.back().properties.push_back(p);
    } else {
      ply_fail(context, "unexpected header line '" + line + "'");
    }
  }
  if (!ended) ply_fail(context, "no end_header line");
  if (format.empty()) ply_fail(context, "no format line");
  if (format != "binary_little_endian" && format != "ascii")
    ply_fail(context,
             "unsupported format '" + format + "' (binary_little_endian and ascii are read)");
  h.binary = format == "binary_little_endian";
  h.data_offset = pos;
  return h;
}

std::string PlyPlace::text() const {
  return element->name + " " + std::to_string(row) + ", property '" + property->name + "'";
}

void PlyBody::truncated(const PlyPlace& at) const {
  ply_fail(context_, "truncated data at " + at.text());
}

double PlyBody::next_text(NumberType type, const PlyPlace& at) {
  char* end = nullptr;
  const double v = std::strtod(p_, &end);
  if (end == p_ || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))))
    ply_fail(context_, "truncated or non-numeric ascii data at " + at.text());
  const char* text = p_;
  p_ = end;
  auto not_of_type = [&]() {
    while (std::isspace(static_cast<unsigned char>(*text))) ++text;
    const std::string value(text, static_cast<const char*>(end));
    ply_fail(context_, "ascii value '" + value + "' at " + at.text() + " is not a " +
                           type_name(type));
  };
  switch (type) {
    case NumberType::Float32:
      if (std::isfinite(v) && std::fabs(v) > double(std::numeric_limits<float>::max()))
        not_of_type();
      return double(float(v));
    case NumberType::Float64: return v;
    default: {
      // Integers: whole, and in range.
      double lo = 0, hi = 0;
      switch (type) {
        case NumberType::Int8: lo = -128, hi = 127; break;
        case NumberType::UInt8: hi = 255; break;
        case NumberType::Int16: lo = -32768, hi = 32767; break;
        case NumberType::UInt16: hi = 65535; break;
        case NumberType::Int32: lo = -2147483648.0, hi = 2147483647.0; break;
        case NumberType::UInt32: hi = 4294967295.0; break;
        default: return v;  // the 64-bit integers are no PLY types
      }
      if (!(v >= lo && v <= hi) || v != std::floor(v)) not_of_type();
      return v;
    }
  }
}

}  // namespace tear
