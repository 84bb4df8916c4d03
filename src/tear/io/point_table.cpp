#include "tear/io/point_table.h"

#include <algorithm>
#include <stdexcept>

namespace tear {

namespace {

std::runtime_error wrong_length(const std::string &name, size_t values, size_t count) {
  return std::runtime_error("column '" + name + "' has " + std::to_string(values) +
                            " values, the table " + std::to_string(count));
}

}  // namespace

void PointTable::add(const std::string &name, ColumnType type, std::vector<double> values) {
  if (values.size() != count) throw wrong_length(name, values.size(), count);
  if (has(name)) throw std::runtime_error("column '" + name + "' added twice");
  names.push_back(name);
  types.push_back(type);
  columns.push_back(std::move(values));
}

bool PointTable::has(const std::string &name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}

bool ColumnNames::add(const std::string &name, std::string *why) {
  if (name.size() > kMaxColumnName)
    *why = "a column name of " + std::to_string(name.size()) + " bytes (at most " +
           std::to_string(kMaxColumnName) + ")";
  else if (names_.size() == kMaxColumns)
    *why = "more than " + std::to_string(kMaxColumns) + " columns";
  else if (!names_.insert(name).second)
    *why = "a second column '" + name + "'";
  else
    return true;
  return false;
}

const std::vector<double> &PointTable::column(const std::string &name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return columns[i];
  throw std::runtime_error("no column '" + name + "'");
}

void PointTable::check_shape() const {
  if (types.size() != names.size() || columns.size() != names.size())
    throw std::runtime_error("table has " + std::to_string(names.size()) + " names, " +
                             std::to_string(types.size()) + " types and " +
                             std::to_string(columns.size()) + " columns");
  for (size_t c = 0; c < names.size(); ++c)
    if (columns[c].size() != count) throw wrong_length(names[c], columns[c].size(), count);
}

std::vector<Eigen::Vector3d> positions(const PointTable &t) {
  std::vector<Eigen::Vector3d> out;
  if (t.count == 0) return out;
  const std::vector<double> &x = t.column("x"), &y = t.column("y");
  const std::vector<double> *z = t.has("z") ? &t.column("z") : nullptr;
  out.reserve(t.count);
  for (size_t i = 0; i < t.count; ++i) out.emplace_back(x[i], y[i], z ? (*z)[i] : 0.0);
  return out;
}

}  // namespace tear
