#include "tear/io/point_table.h"

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"

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

PointRows rows_of(const PointTable &t) {
  t.check_shape();
  PointRows r;
  r.count = t.count;
  r.names = t.names;
  r.types = t.types;
  r.fill = [&t](size_t begin, size_t n, double *const *out) {
    for (size_t c = 0; c < t.columns.size(); ++c)
      std::copy_n(t.columns[c].data() + begin, n, out[c]);
  };
  return r;
}

void fill_table(const PointRows &rows, PointTable *table) {
  PointTable &t = *table;
  if (t.names != rows.names || t.types != rows.types) {
    t = PointTable();
    t.names = rows.names;
    t.types = rows.types;
    t.columns.resize(rows.names.size());
  }
  t.count = rows.count;
  for (std::vector<double> &c : t.columns) reserve_large(&c, rows.count), c.resize(rows.count);
  constexpr size_t kChunk = 4096;
  parallel_for((rows.count + kChunk - 1) / kChunk, [&](size_t chunk) {
    const size_t begin = chunk * kChunk, n = std::min(rows.count, begin + kChunk) - begin;
    std::vector<double *> out(t.columns.size());
    for (size_t c = 0; c < out.size(); ++c) out[c] = t.columns[c].data() + begin;
    rows.fill(begin, n, out.data());
  });
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
