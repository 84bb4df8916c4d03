// io/: the numbers the point and mesh readers meet in files: the binary value types of PLY and
// VTU (each format names them its own way), read as double, and decimal counts in headers.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "tear/io/endian.h"
#include "tear/io/point_table.h"

namespace tear {

enum class NumberType {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Int64,
  UInt64,
  Float32,
  Float64
};

inline size_t number_size(NumberType t) {
  switch (t) {
    case NumberType::Int8:
    case NumberType::UInt8: return 1;
    case NumberType::Int16:
    case NumberType::UInt16: return 2;
    case NumberType::Int32:
    case NumberType::UInt32:
    case NumberType::Float32: return 4;
    case NumberType::Int64:
    case NumberType::UInt64:
    case NumberType::Float64: return 8;
  }
  return 0;
}

// The little-endian value of type `t` at `p`.
inline double load_le_number(NumberType t, const char* p) {
  switch (t) {
    case NumberType::Int8: return load_le<int8_t>(p);
    case NumberType::UInt8: return load_le<uint8_t>(p);
    case NumberType::Int16: return load_le<int16_t>(p);
    case NumberType::UInt16: return load_le<uint16_t>(p);
    case NumberType::Int32: return load_le<int32_t>(p);
    case NumberType::UInt32: return load_le<uint32_t>(p);
    case NumberType::Int64: return double(load_le<int64_t>(p));
    case NumberType::UInt64: return double(load_le<uint64_t>(p));
    case NumberType::Float32: return load_le<float>(p);
    case NumberType::Float64: return load_le<double>(p);
  }
  return 0;
}

// The table column type that holds every value of `t` exactly: the signed 8/16-bit types and
// uint16 do not fit uchar, so they become int32; uint32 (beyond 2^31) and the 64-bit integers
// become double.
inline ColumnType exact_column_type(NumberType t) {
  switch (t) {
    case NumberType::UInt8: return ColumnType::UInt8;
    case NumberType::Int8:
    case NumberType::Int16:
    case NumberType::UInt16:
    case NumberType::Int32: return ColumnType::Int32;
    case NumberType::Float32: return ColumnType::Float32;
    case NumberType::UInt32:
    case NumberType::Int64:
    case NumberType::UInt64:
    case NumberType::Float64: return ColumnType::Float64;
  }
  return ColumnType::Float64;
}

// The shortest decimal text that reads back as exactly `v` (a float or a double).
template <class T>
std::string shortest_text(T v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof(buf), v).ptr);
}

// A non-negative decimal count: all digits, no sign, at most 18 of them (so no overflow).
inline bool parse_count(const std::string& text, size_t* n) {
  if (text.empty() || text.size() > 18) return false;
  for (char c : text)
    if (c < '0' || c > '9') return false;
  *n = size_t(std::strtoull(text.c_str(), nullptr, 10));
  return true;
}

// A whole token as a number: decimal or exponent notation (from_chars: no leading '+'), or an
// integer of at most 18 digits with an optional '-'. False for anything else.
inline bool parse_real(std::string_view text, double* v) {
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, *v);
  return r.ec == std::errc() && r.ptr == end;
}
inline bool parse_integer(std::string_view text, int64_t* v) {
  if (text.empty() || text.size() > 19) return false;
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, *v);
  return r.ec == std::errc() && r.ptr == end;
}

}  // namespace tear
