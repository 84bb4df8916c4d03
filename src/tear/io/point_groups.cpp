#include "tear/io/point_groups.h"

#include <algorithm>
#include <stdexcept>

namespace tear {

namespace {

const char* name_in(const VectorGroup& g, AttributeFormat format) {
  return format == AttributeFormat::Bgeo ? g.bgeo : g.vtu;
}

int find_column(const PointTable& t, const char* name) {
  const auto it = std::find(t.names.begin(), t.names.end(), name);
  return it == t.names.end() ? -1 : int(it - t.names.begin());
}

}  // namespace

const std::vector<VectorGroup>& vector_groups() {
  static const std::vector<VectorGroup> kGroups{
      {{"x", "y", "z"}, "P", "Points"},
      {{"vx", "vy", "vz"}, "v", "velocity"},
      {{"fx", "fy", "fz"}, "fiber", "fiber"},
  };
  return kGroups;
}

std::vector<PointAttribute> group_columns(const PointTable& t, AttributeFormat format) {
  t.check_shape();
  const size_t n = t.names.size();

  // For each column, the attribute it starts (its own, or its vector group's), or -1 when it
  // is a later component of a group.
  std::vector<int> group_of(n, -2);  // -2: a scalar of its own
  std::vector<PointAttribute> grouped;
  for (const VectorGroup& g : vector_groups()) {
    int cols[3];
    for (int k = 0; k < 3; ++k) cols[k] = find_column(t, g.columns[k]);
    if (cols[0] < 0 || cols[1] < 0) continue;
    PointAttribute a;
    a.name = name_in(g, format);
    a.position = &g == &vector_groups().front();
    for (int k = 0; k < 3; ++k) {
      a.components.push_back(cols[k] < 0 ? nullptr : &t.columns[size_t(cols[k])]);
      if (cols[k] >= 0) {
        a.float64 = a.float64 || t.types[size_t(cols[k])] == ColumnType::Float64;
        group_of[size_t(cols[k])] = -1;
      }
    }
    const int first = cols[2] < 0 ? std::min(cols[0], cols[1]) : *std::min_element(cols, cols + 3);
    group_of[size_t(first)] = int(grouped.size());
    grouped.push_back(std::move(a));
  }

  std::vector<PointAttribute> out;
  for (size_t c = 0; c < n; ++c) {
    if (group_of[c] >= 0) {
      out.push_back(grouped[size_t(group_of[c])]);
    } else if (group_of[c] == -2) {
      PointAttribute a;
      a.name = t.names[c];
      a.components = {&t.columns[c]};
      a.integer = t.types[c] == ColumnType::Int32 || t.types[c] == ColumnType::UInt8;
      a.float64 = t.types[c] == ColumnType::Float64;
      out.push_back(std::move(a));
    }
  }
  for (size_t i = 0; i < out.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (out[i].name == out[j].name)
        throw std::runtime_error("two attributes would be named '" + out[i].name +
                                 "' (a column of that name beside the columns that form it); " +
                                 "rename the column");
  return out;
}

std::vector<std::string> attribute_columns(const std::string& name, int size,
                                           AttributeFormat format) {
  if (size == 3)
    for (const VectorGroup& g : vector_groups())
      if (name == name_in(g, format)) return {g.columns[0], g.columns[1], g.columns[2]};
  if (size == 1) return {name};
  std::vector<std::string> out;
  for (int k = 0; k < size; ++k) out.push_back(name + "_" + std::to_string(k));
  return out;
}

}  // namespace tear
