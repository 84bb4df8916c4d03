// io/: the header of a PLY file and its body read value by value, shared by the point reader
// (ply.cpp) and the mesh reader (mesh_io.cpp). Knows nothing of points or meshes.
#pragma once

#include <string>
#include <vector>

#include "tear/io/numbers.h"

namespace tear {

struct PlyProperty {
  std::string name;
  NumberType type = NumberType::Float32;  // of the value, or of each item of a list
  bool list = false;
  NumberType count_type = NumberType::UInt8;  // of a list's length
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool binary = false;  // binary_little_endian; otherwise ascii
  std::vector<PlyElement> elements;
  size_t data_offset = 0;  // where the body starts, just after the end_header line
};

// Every PLY error is std::runtime_error("<context>: <why>"), `context` naming the reader
// ("bad PLY", "bad PLY mesh").
[[noreturn]] void ply_fail(const char* context, const std::string& why);

// The header of `bytes` up to end_header: comment and obj_info lines skipped, every property of
// a known scalar type (old or sized name) and named, the format ascii or binary_little_endian.
PlyHeader parse_ply_header(const std::string& bytes, const char* context);

// Where a value is, for error messages: "face 2, property 'vertex_indices'".
struct PlyPlace {
  const PlyElement* element = nullptr;
  size_t row = 0;
  const PlyProperty* property = nullptr;
  std::string text() const;
};

// The body of a PLY file, value by value, in the header's format; reads past the end are
// errors that name the value's place. An ascii value must be one of its type, as a binary
// file's value is: an integer in the type's range, a float rounded to float (an ascii "300" for a
// uchar or "1.5" for an int is an error, not a value the table's column cannot hold).
class PlyBody {
 public:
  // `bytes` must outlive the reader.
  PlyBody(const std::string& bytes, const PlyHeader& header, const char* context)
      : p_(bytes.c_str() + header.data_offset),
        end_(bytes.c_str() + bytes.size()),
        binary_(header.binary),
        context_(context) {}

  double next(NumberType type, const PlyPlace& at) {
    if (!binary_) return next_text(type, at);
    const size_t size = number_size(type);
    if (size_t(end_ - p_) < size) truncated(at);
    const double v = load_le_number(type, p_);
    p_ += size;
    return v;
  }
  size_t remaining() const { return size_t(end_ - p_); }

 private:
  double next_text(NumberType type, const PlyPlace& at);
  [[noreturn]] void truncated(const PlyPlace& at) const;

  const char* p_;  // the next value; *end_ is '\0' (std::string::c_str)
  const char* end_;
  bool binary_;
  const char* context_;
};

}  // namespace tear
