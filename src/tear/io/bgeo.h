// io/: Houdini classic binary geometry ("Bgeo" version 5, the layout partio reads and writes):
// points only, with point attributes grouped by io/point_groups.h.
#pragma once

#include <string>

#include "tear/io/point_table.h"

namespace tear {

// Big-endian throughout: "Bgeo", 'V', int32 5, eight int32 counts (points, primitives 0, point
// groups 0, primitive groups 0, point attributes, vertex 0, primitive 0, detail 0), each point
// attribute as int16 name length, name, int16 components, int32 type (0 float, 1 int,
// 5 vector) and a zero default per component; then per point P as 4 floats (x, y, z, w = 1)
// and each attribute's components (float or int32); then the bytes 0x00 0xff.
// Vector groups become "P" (position, required), "v", "fiber"; every other column an attribute
// of its own name, int for Int32/UInt8 columns, float otherwise (Float64 loses precision).
std::string encode_bgeo(const PointTable& table);

// The table of a points-only classic BGEO (what encode_bgeo writes, or a Houdini/partio file:
// primitives, groups and detail attributes after the points are ignored). Columns: x y z first,
// then each attribute in file order (attribute_columns() names them); float attributes become
// Float32 columns and int ones Int32, so encode then decode gives the same columns and values
// with UInt8 as Int32 and Float64 rounded to Float32. Throws std::runtime_error with the reason
// (bad magic, version, truncation, an unsupported attribute type).
PointTable decode_bgeo(const std::string& bytes);

}  // namespace tear
