// io/: PLY point files (one "vertex" element, one property per column).
#pragma once

#include <string>
#include <vector>

namespace tear {

enum class PlyType { Int32, UInt8, Float32, Float64 };

// A table of per-vertex columns. Values are held as double in memory and converted to the
// column's declared type when encoded.
struct PlyTable {
  size_t count = 0;
  std::vector<std::string> names;
  std::vector<PlyType> types;
  std::vector<std::vector<double>> columns;

  // Append a column; `values.size()` must equal `count`.
  void add(const std::string& name, PlyType type, std::vector<double> values);
  bool has(const std::string& name) const;
  // Throws std::runtime_error if absent.
  const std::vector<double>& column(const std::string& name) const;
};

// "ply / format binary_little_endian 1.0 / element vertex N / property ... / end_header".
std::string encode_ply(const PlyTable& table);
// Reads binary_little_endian and ascii PLY with a single vertex element (any scalar types).
// Throws std::runtime_error with the reason on malformed input.
PlyTable decode_ply(const std::string& bytes);

}  // namespace tear
