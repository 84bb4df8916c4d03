// io/: PLY point files (one "vertex" element, one property per column).
#pragma once

#include "tear/io/point_table.h"

#include <string>

namespace tear {

// "ply / format binary_little_endian 1.0 / element vertex N / property ... / end_header".
std::string encode_ply(const PointTable& table);
// The same from rows made on demand, into `out` (whose storage is reused: a run keeps one buffer
// for all its frames).
void encode_ply(const PointRows& rows, std::string* out);
// Reads binary_little_endian and ascii PLY with a single vertex element (any scalar types).
// Throws std::runtime_error with the reason on malformed input.
PointTable decode_ply(const std::string& bytes);

}  // namespace tear
