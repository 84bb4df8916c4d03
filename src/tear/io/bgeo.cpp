#include "tear/io/bgeo.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "tear/io/endian.h"
#include "tear/io/point_groups.h"

namespace tear {

namespace {

// Houdini's attribute types (the ones a points-only file uses).
constexpr int32_t kFloat = 0, kInt = 1, kIndexedString = 4, kVector = 5;

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error("bad BGEO: " + why); }

// Bounds-checked big-endian reads; `what` names the part being read in the error.
class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    const T v = load_be<T>(bytes_.data() + pos_);
    pos_ += sizeof(T);
    return v;
  }
  std::string text(size_t n, const char* what) {
    need(n, what);
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  void skip(size_t n, const char* what) {
    need(n, what);
    pos_ += n;
  }
  void need(size_t n, const std::string& what) const {
    if (bytes_.size() - pos_ < n)
      fail("truncated: " + what + " needs " + std::to_string(n) + " bytes at offset " +
           std::to_string(pos_) + ", the file has " + std::to_string(bytes_.size() - pos_) +
           " left");
  }
  const char* here() const { return bytes_.data() + pos_; }
  size_t left() const { return bytes_.size() - pos_; }

 private:
  const std::string& bytes_;
  size_t pos_ = 0;
};

}  // namespace

std::string encode_bgeo(const PointTable& t) {
  const std::vector<PointAttribute> attrs = group_columns(t, AttributeFormat::Bgeo);
  const auto p =
      std::find_if(attrs.begin(), attrs.end(), [](const PointAttribute& a) { return a.position; });
  if (p == attrs.end()) throw std::runtime_error("BGEO needs the position columns x, y (and z)");
  if (t.count > size_t(std::numeric_limits<int32_t>::max()))
    throw std::runtime_error("BGEO holds at most 2^31 - 1 points, the table has " +
                             std::to_string(t.count));

  std::string out = "BgeoV";
  append_be<int32_t>(&out, 5);
  const int32_t counts[8] = {int32_t(t.count), 0, 0, 0, int32_t(attrs.size() - 1), 0, 0, 0};
  for (int32_t c : counts) append_be(&out, c);
  size_t words = 4;  // P: x y z w
  for (const PointAttribute& a : attrs) {
    if (a.position) continue;
    if (a.name.size() > size_t(std::numeric_limits<int16_t>::max()))
      throw std::runtime_error("BGEO attribute name longer than 32767 bytes");
    append_be<int16_t>(&out, int16_t(a.name.size()));
    out += a.name;
    const int16_t size = int16_t(a.components.size());
    append_be<int16_t>(&out, size);
    append_be<int32_t>(&out, a.integer ? kInt : size == 3 ? kVector : kFloat);
    for (int k = 0; k < size; ++k) append_be<int32_t>(&out, 0);  // default value
    words += size_t(size);
  }

  const size_t header = out.size();
  out.resize(header + 4 * words * t.count);
  char* w = &out[header];
  for (size_t i = 0; i < t.count; ++i) {
    for (const std::vector<double>* c : p->components)
      store_be(w, c ? float((*c)[i]) : 0.0f), w += 4;
    store_be(w, 1.0f), w += 4;  // homogeneous w
    for (const PointAttribute& a : attrs) {
      if (a.position) continue;
      for (const std::vector<double>* c : a.components) {
        const double v = c ? (*c)[i] : 0.0;
        if (a.integer)
          store_be(w, int32_t(v));
        else
          store_be(w, float(v));
        w += 4;
      }
    }
  }
  // No primitives, no detail attributes; partio ends every file with these two bytes.
  out += '\x00';
  out += '\xff';
  return out;
}

PointTable decode_bgeo(const std::string& bytes) {
  if (bytes.size() >= 2 && bytes[0] == '\x1f' && bytes[1] == '\x8b')
    fail("gzip-compressed (.bgeo.gz); decompress it first");
  if (bytes.size() >= 4 && bytes.compare(0, 4, "\x7fNSJ") == 0)
    fail("the new (Houdini 12+) binary format; save it as classic geometry (.bhclassic)");
  if (bytes.size() < 4) fail("truncated: " + std::to_string(bytes.size()) + " bytes");
  if (bytes.compare(0, 4, "Bgeo") != 0) fail("bad magic (expected \"Bgeo\")");
  Reader r(bytes);
  r.skip(4, "magic");
  if (r.get<char>("version") != 'V') fail("bad version marker (expected 'V' after \"Bgeo\")");
  const int32_t version = r.get<int32_t>("version");
  if (version != 5) fail("version " + std::to_string(version) + " (only version 5 is read)");
  const char* names[8] = {
      "points",           "primitives",        "point groups",         "primitive groups",
      "point attributes", "vertex attributes", "primitive attributes", "detail attributes"};
  int32_t counts[8];
  for (int k = 0; k < 8; ++k) {
    counts[k] = r.get<int32_t>("header");
    if (counts[k] < 0) fail(std::string("negative count of ") + names[k]);
  }
  const size_t n = size_t(counts[0]);

  PointTable t;
  t.count = n;
  struct Attr {
    int32_t type;
    size_t size;
  };
  std::vector<Attr> attrs;
  ColumnNames columns;
  std::string why;
  auto add_columns = [&](const std::string& name, size_t size, ColumnType type) {
    // Checked before making the names: a long name of many components would make many long ones.
    if (name.size() > kMaxColumnName)
      fail("an attribute name of " + std::to_string(name.size()) + " bytes (at most " +
           std::to_string(kMaxColumnName) + ")");
    if (t.names.size() + size > kMaxColumns)
      fail("attribute '" + name + "' of " + std::to_string(size) + " components makes more than " +
           std::to_string(kMaxColumns) + " columns");
    for (const std::string& c : attribute_columns(name, int(size), AttributeFormat::Bgeo)) {
      if (!columns.add(c, &why)) fail("attribute '" + name + "' gives " + why);
      t.names.push_back(c);
      t.types.push_back(type);
    }
  };
  add_columns("P", 3, ColumnType::Float32);
  size_t words = 4;
  for (int32_t a = 0; a < counts[4]; ++a) {
    const uint16_t length = r.get<uint16_t>("attribute name length");
    const std::string name = r.text(length, "attribute name");
    const uint16_t size = r.get<uint16_t>("attribute size");
    const int32_t type = r.get<int32_t>("attribute type");
    if (name.empty()) fail("attribute " + std::to_string(a) + " has no name");
    if (size == 0) fail("attribute '" + name + "' has 0 components");
    if (type == kIndexedString) fail("attribute '" + name + "' is an indexed string (not read)");
    if (type != kFloat && type != kInt && type != kVector)
      fail("attribute '" + name + "' has type " + std::to_string(type) +
           " (float 0, int 1 and vector 5 are read)");
    r.skip(4 * size_t(size), "attribute default");
    add_columns(name, size, type == kInt ? ColumnType::Int32 : ColumnType::Float32);
    attrs.push_back({type, size});
    words += size;
  }

  // Checked before allocating, so a corrupt count cannot ask for terabytes.
  if (n > r.left() / (4 * words))
    fail("truncated: " + std::to_string(n) + " points of " + std::to_string(4 * words) +
         " bytes, found " + std::to_string(r.left()) + " bytes of point data");
  t.columns.assign(t.names.size(), std::vector<double>(n));
  for (size_t i = 0; i < n; ++i) {
    const char* p = r.here();
    for (int k = 0; k < 3; ++k) t.columns[size_t(k)][i] = load_be<float>(p + 4 * k);
    p += 16;  // w is not kept
    size_t c = 3;
    for (const Attr& a : attrs)
      for (size_t k = 0; k < a.size; ++k, ++c, p += 4)
        t.columns[c][i] = a.type == kInt ? double(load_be<int32_t>(p)) : double(load_be<float>(p));
    r.skip(4 * words, "point");
  }

  // A points-only file ends with 0x00 0xff; anything else after the points (primitives, groups,
  // detail attributes of a Houdini file) is not needed for the points and not checked.
  bool points_only = true;
  for (int k = 1; k < 8; ++k) points_only = points_only && (k == 4 || counts[k] == 0);
  if (points_only) {
    if (r.left() < 2) fail("truncated: the end bytes 0x00 0xff are missing");
    if (r.here()[0] != '\x00' || r.here()[1] != '\xff')
      fail("bad end bytes after the points (expected 0x00 0xff)");
    if (r.left() > 2) fail(std::to_string(r.left() - 2) + " unexpected bytes after the end");
  }
  return t;
}

}  // namespace tear
