#include "tear/io/point_table.h"

#include <algorithm>
#include <stdexcept>

namespace tear {

void PointTable::add(const std::string &name, ColumnType type, std::vector<double> values) {
  if (values.size() != count)
    throw std::runtime_error("column '" + name + "' has " + std::to_string(values.size()) +
                             " values, the table " + std::to_string(count));
  if (has(name)) throw std::runtime_error("column '" + name + "' added twice");
  names.push_back(name);
  types.push_back(type);
  columns.push_back(std::move(values));
}

bool PointTable::has(const std::string &name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}

const std::vector<double> &PointTable::column(const std::string &name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return columns[i];
  throw std::runtime_error("no column '" + name + "'");
}

}  // namespace tear
