// io/: which columns of a PointTable travel together as one attribute in the point formats that
// have vector attributes (BGEO, VTU), and under which names. The one place that says so;
// docs/outputs.md lists the resulting names. Knows nothing of either file layout.
#pragma once

#include <string>
#include <vector>

#include "tear/io/point_table.h"

namespace tear {

// A 3-vector made of three table columns.
struct VectorGroup {
  const char* columns[3];  // table columns, in component order
  const char* bgeo;        // BGEO point attribute ("P": the point position itself)
  const char* vtu;         // VTU point array ("Points": the <Points> element)
};

// Position (x y z -> P / Points), velocity (vx vy vz -> v / velocity), fiber direction
// (fx fy fz -> fiber / fiber), position first.
const std::vector<VectorGroup>& vector_groups();

enum class AttributeFormat { Bgeo, Vtu };

// One attribute (BGEO) or point array (VTU) to write.
struct PointAttribute {
  std::string name;  // in the target format
  // One column (a scalar) or three (a vector group); nullptr where a vector group's third
  // column is absent (a 2D table without z): written as 0.
  std::vector<const std::vector<double>*> components;
  bool integer = false;   // a scalar Int32 or UInt8 column; vector groups are always float
  bool float64 = false;   // some component is a Float64 column (VTU keeps the precision)
  bool position = false;  // the position group: BGEO "P", VTU <Points>
};

// The attributes of `t`: a vector group wherever the first two of its columns are present
// (in the place of its first column), every other column as a scalar under its own name, in
// table order. Throws std::runtime_error when the table is inconsistent or two attributes would
// have the same name (e.g. a column "v" next to vx vy vz in BGEO).
std::vector<PointAttribute> group_columns(const PointTable& t, AttributeFormat format);

// The table columns that an attribute `name` of `size` components decodes to: a vector group's
// columns where `name` is its name in `format` and size is 3, {name} for one component, and
// name_0 .. name_{size-1} for any other attribute of several components.
std::vector<std::string> attribute_columns(const std::string& name, int size,
                                           AttributeFormat format);

}  // namespace tear
