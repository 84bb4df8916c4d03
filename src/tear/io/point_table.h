// io/: the format-neutral table of per-point columns that every point format
// (PLY, BGEO, VTU) encodes and decodes, and that mesh and render read frames
// into.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <unordered_set>
#include <vector>

#include "tear/particles/field.h"  // ColumnType

namespace tear {

// A table of per-point columns. Values are held as double in memory and
// converted to the column's declared type when encoded.
struct PointTable {
  size_t count = 0;
  std::vector<std::string> names;
  std::vector<ColumnType> types;
  std::vector<std::vector<double>> columns;

  // Append a column; `values.size()` must equal `count`.
  void add(const std::string &name, ColumnType type, std::vector<double> values);
  bool has(const std::string &name) const;
  // Throws std::runtime_error if absent.
  const std::vector<double> &column(const std::string &name) const;
  // Throws std::runtime_error unless names, types and columns agree in number and every column
  // holds `count` values (what the encoders rely on).
  void check_shape() const;
};

// The rows of a table made on demand, a chunk at a time: what a frame encoder reads instead of
// a whole PointTable (a frame of 475k particles held as doubles is 46 MB that nobody keeps).
struct PointRows {
  size_t count = 0;
  std::vector<std::string> names;
  std::vector<ColumnType> types;
  // Writes column c of rows [begin, begin + n) to out[c][0 .. n), for every column. Called
  // from several threads at once, each with its own chunk.
  std::function<void(size_t begin, size_t n, double *const *out)> fill;
};

// A table's rows (the view refers to `t`, which must outlive it).
PointRows rows_of(const PointTable &t);
// All of `rows` into `table`, in parallel chunks, reusing its columns' storage when it has the
// same names and types (fresh pages cost more than the copy).
void fill_table(const PointRows &rows, PointTable *table);

// Limits of the point readers (PLY, BGEO, VTU), far beyond a frame's few dozen columns of short
// names: a corrupt count or name length gets a clear error instead of millions of column names.
constexpr size_t kMaxColumns = 4096;
constexpr size_t kMaxColumnName = 1024;

// The column names a reader has added to a table so far, checked as they come: unique (looked up
// in a hash set, so that wide tables read in linear time), at most kMaxColumns of them, each at
// most kMaxColumnName bytes long.
class ColumnNames {
 public:
  // Adds `name`, or returns false with the reason in `why` ("a second column 'vx'").
  bool add(const std::string &name, std::string *why);
  bool has(const std::string &name) const { return names_.count(name) != 0; }

 private:
  std::unordered_set<std::string> names_;
};

// Columns x, y and z (0 where the table has no z) as points; none for an empty table. Throws
// std::runtime_error when a non-empty table has no x or y.
std::vector<Eigen::Vector3d> positions(const PointTable &t);

}  // namespace tear
