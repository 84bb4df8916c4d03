#include "tear/io/ply.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "tear/exec/memory.h"
#include "tear/exec/parallel.h"
#include "tear/io/endian.h"
#include "tear/io/ply_header.h"

namespace tear {

namespace {

constexpr const char* kContext = "bad PLY";

[[noreturn]] void fail(const std::string& why) { ply_fail(kContext, why); }

struct TypeInfo {
  const char* name;
  size_t size;
};

TypeInfo info(ColumnType t) {
  switch (t) {
    case ColumnType::Int32: return {"int", 4};
    case ColumnType::UInt8: return {"uchar", 1};
    case ColumnType::Float32: return {"float", 4};
    case ColumnType::Float64: return {"double", 8};
  }
  return {"?", 0};
}

}  // namespace

void encode_ply(const PointRows& rows, std::string* out) {
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by tear\nelement vertex " +
      std::to_string(rows.count) + "\n";
  size_t row = 0;
  for (size_t c = 0; c < rows.names.size(); ++c) {
    header += "property " + std::string(info(rows.types[c]).name) + " " + rows.names[c] + "\n";
    row += info(rows.types[c]).size;
  }
  header += "end_header\n";
  // Every byte is written below: a buffer kept from the last frame is not cleared first.
  reserve_large(out, header.size() + row * rows.count);
  out->resize(header.size() + row * rows.count);
  std::copy(header.begin(), header.end(), out->begin());
  // Vertex-major: row i holds every column's value i. Values must fit the column's type. Rows
  // are independent: chunks of them in parallel, each made into a small table first.
  constexpr size_t kRows = 4096;
  const size_t columns = rows.names.size();
  parallel_for((rows.count + kRows - 1) / kRows, [&](size_t chunk) {
    const size_t begin = chunk * kRows, n = std::min(rows.count, begin + kRows) - begin;
    thread_local std::vector<double> values;
    thread_local std::vector<double*> column;
    values.resize(columns * kRows);
    column.resize(columns);
    for (size_t c = 0; c < columns; ++c) column[c] = values.data() + c * kRows;
    rows.fill(begin, n, column.data());
    char* p = &(*out)[header.size() + begin * row];
    for (size_t i = 0; i < n; ++i) {
      for (size_t c = 0; c < columns; ++c) {
        const double v = column[c][i];
        switch (rows.types[c]) {
          case ColumnType::Int32: store_le(p, int32_t(v)), p += 4; break;
          case ColumnType::UInt8: store_le(p, uint8_t(v)), p += 1; break;
          case ColumnType::Float32: store_le(p, float(v)), p += 4; break;
          case ColumnType::Float64: store_le(p, v), p += 8; break;
        }
      }
    }
  });
}

std::string encode_ply(const PointTable& t) {
  std::string out;
  encode_ply(rows_of(t), &out);
  return out;
}

PointTable decode_ply(const std::string& bytes) {
  const PlyHeader h = parse_ply_header(bytes, kContext);
  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : h.elements) {
    if (e.name != "vertex") {
      // Other elements may be declared (e.g. "face 0") but not hold data.
      if (e.count != 0) fail("element '" + e.name + "' has data; only 'vertex' is supported");
    } else if (vertex) {
      fail("two vertex elements");
    } else {
      vertex = &e;
    }
  }
  if (!vertex) fail("no vertex element");

  PointTable t;
  t.count = vertex->count;
  size_t row = 0;  // bytes, in binary
  ColumnNames names;
  std::string why;
  for (const PlyProperty& p : vertex->properties) {
    if (p.list) fail("list properties are not supported (property '" + p.name + "')");
    if (names.has(p.name)) fail("property '" + p.name + "' appears twice");
    if (!names.add(p.name, &why)) fail("property '" + p.name + "': " + why);
    t.names.push_back(p.name);
    t.types.push_back(exact_column_type(p.type));
    row += number_size(p.type);
  }

  // Checked before allocating, so a corrupt count cannot ask for terabytes.
  const size_t available = bytes.size() - h.data_offset;
  const size_t cols = t.names.size();
  // Rows without values would be a table of no columns: nothing to read, however many.
  if (cols == 0 && t.count > 0)
    fail("element 'vertex' has " + std::to_string(t.count) + " rows but no properties");
  if (h.binary && row > 0 && t.count > available / row)
    fail("truncated: " + std::to_string(t.count) + " vertices of " + std::to_string(row) +
         " bytes, found " + std::to_string(available) + " bytes of data");
  // In ascii every value takes at least one character and a separator.
  if (!h.binary && cols > 0 && t.count > (available + 1) / 2 / cols)
    fail("truncated: " + std::to_string(t.count) + " vertices of " + std::to_string(cols) +
         " values cannot fit in " + std::to_string(available) + " bytes of data");
  t.columns.assign(cols, std::vector<double>(t.count));
  PlyBody body(bytes, h, kContext);
  PlyPlace at;
  at.element = vertex;
  for (size_t i = 0; i < t.count; ++i) {
    at.row = i;
    for (size_t c = 0; c < cols; ++c) {
      at.property = &vertex->properties[c];
      t.columns[c][i] = body.next(at.property->type, at);
    }
  }
  return t;
}

}  // namespace tear
