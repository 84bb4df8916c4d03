#include "tear/io/vtk_xml.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "tear/io/endian.h"

namespace tear {

namespace {

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error("bad VTU: " + why); }

// --- base64 (RFC 4648, with padding)

const char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

}  // namespace

std::string base64_encode(const std::string& in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 |
                       uint32_t(uint8_t(in[i + 2]));
    for (int s = 18; s >= 0; s -= 6) out += kBase64[(v >> s) & 63];
  }
  if (i < in.size()) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += i + 1 < in.size() ? kBase64[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

// Whitespace is skipped; padding may end a quad anywhere, since some writers encode the header
// and the data as two base64 runs one after the other.
std::string base64_decode(const char* p, const char* end, const std::string& array) {
  int value[256];
  std::fill(value, value + 256, -1);
  for (int k = 0; k < 64; ++k) value[uint8_t(kBase64[k])] = k;
  std::string out;
  out.reserve(size_t(end - p) / 4 * 3);
  uint32_t quad = 0;
  int have = 0, pad = 0;
  for (; p < end; ++p) {
    const unsigned char c = uint8_t(*p);
    if (std::isspace(c)) continue;
    if (c == '=') {
      if (have < 2) fail("array '" + array + "': misplaced '=' in its base64 data");
      ++pad;
    } else if (value[c] < 0 || pad > 0) {
      fail("array '" + array + "': invalid base64 data");
    }
    quad = quad << 6 | uint32_t(c == '=' ? 0 : value[c]);
    if (++have == 4) {
      out += char(quad >> 16);
      if (pad < 2) out += char(quad >> 8 & 255);
      if (pad < 1) out += char(quad & 255);
      quad = 0;
      have = pad = 0;
    }
  }
  if (have != 0) fail("array '" + array + "': base64 data ends inside a group of four");
  return out;
}

// --- VTK value types

struct VtkType {
  const char* name;
  NumberType number;
};

const VtkType kTypes[] = {
    {"Int8", NumberType::Int8},       {"UInt8", NumberType::UInt8},
    {"Int16", NumberType::Int16},     {"UInt16", NumberType::UInt16},
    {"Int32", NumberType::Int32},     {"UInt32", NumberType::UInt32},
    {"Int64", NumberType::Int64},     {"UInt64", NumberType::UInt64},
    {"Float32", NumberType::Float32}, {"Float64", NumberType::Float64},
};

const VtkType* find_type(const std::string& name) {
  for (const VtkType& t : kTypes)
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// --- XML: just enough for the files encode_vtu and encode_pvd write

std::string xml_unescape(const std::string& s) {
  static const struct {
    const char* entity;
    char c;
  } kEntities[] = {{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < s.size();) {
    bool replaced = false;
    if (s[i] == '&')
      for (const auto& e : kEntities)
        if (s.compare(i, std::strlen(e.entity), e.entity) == 0) {
          out += e.c;
          i += std::strlen(e.entity);
          replaced = true;
          break;
        }
    if (!replaced) out += s[i++];
  }
  return out;
}

struct Tag {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attrs;
  bool closing = false, empty = false;
  size_t end = 0;  // just after '>'
  const std::string* attr(const char* key) const {
    for (const auto& [k, v] : attrs)
      if (k == key) return &v;
    return nullptr;
  }
};

// The next element tag at or after `pos` (skipping text, <?...?> and <!--...-->); false at the
// end of the document.
bool next_tag(const std::string& s, size_t pos, Tag* tag) {
  for (;;) {
    pos = s.find('<', pos);
    if (pos == std::string::npos) return false;
    if (s.compare(pos, 2, "<?") == 0 || s.compare(pos, 4, "<!--") == 0) {
      const bool pi = s[pos + 1] == '?';
      const size_t e = s.find(pi ? "?>" : "-->", pos);
      if (e == std::string::npos) fail(pi ? "unterminated <?" : "unterminated comment");
      pos = e + (pi ? 2 : 3);
      continue;
    }
    break;
  }
  *tag = Tag();
  size_t i = pos + 1;
  if (i < s.size() && s[i] == '/') tag->closing = true, ++i;
  auto is_name = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' ||
           c == '.';
  };
  const size_t name_start = i;
  while (i < s.size() && is_name(s[i])) ++i;
  tag->name = s.substr(name_start, i - name_start);
  if (tag->name.empty()) fail("malformed tag at offset " + std::to_string(pos));
  for (;;) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= s.size()) fail("unterminated <" + tag->name + "> tag");
    if (s[i] == '>') {
      tag->end = i + 1;
      return true;
    }
    if (s.compare(i, 2, "/>") == 0) {
      tag->empty = true;
      tag->end = i + 2;
      return true;
    }
    const size_t key_start = i;
    while (i < s.size() && is_name(s[i])) ++i;
    const std::string key = s.substr(key_start, i - key_start);
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (key.empty() || i + 1 >= s.size() || s[i] != '=')
      fail("malformed attribute in <" + tag->name + ">");
    ++i;
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= s.size() || (s[i] != '"' && s[i] != '\''))
      fail("attribute " + key + " of <" + tag->name + "> is not quoted");
    const size_t close = s.find(s[i], i + 1);
    if (close == std::string::npos) fail("unterminated attribute " + key);
    tag->attrs.emplace_back(key, xml_unescape(s.substr(i + 1, close - i - 1)));
    i = close + 1;
  }
}

// A count attribute's value; `what` names it in the error.
size_t count_attribute(const std::string& text, const std::string& what) {
  size_t n = 0;
  if (!parse_count(text, &n)) fail(what + " \"" + text + "\" is not a count");
  return n;
}

// Whether an ascii value `v` is one that type `t` holds, made what it holds: rounded to float for
// Float32 (whose range it must be in, or infinite or NaN), whole and in range for the integers.
bool hold_as(NumberType t, double* v) {
  const double x = *v;
  switch (t) {
    case NumberType::Float64: return true;
    case NumberType::Float32:
      if (std::isfinite(x) && std::fabs(x) > double(std::numeric_limits<float>::max()))
        return false;
      *v = double(float(x));
      return true;
    case NumberType::Int8: return x == std::floor(x) && x >= -128 && x <= 127;
    case NumberType::UInt8: return x == std::floor(x) && x >= 0 && x <= 255;
    case NumberType::Int16: return x == std::floor(x) && x >= -32768 && x <= 32767;
    case NumberType::UInt16: return x == std::floor(x) && x >= 0 && x <= 65535;
    case NumberType::Int32: return x == std::floor(x) && x >= -2147483648.0 && x <= 2147483647.0;
    case NumberType::UInt32: return x == std::floor(x) && x >= 0 && x <= 4294967295.0;
    case NumberType::Int64: return x == std::floor(x) && x >= -0x1p63 && x < 0x1p63;
    case NumberType::UInt64: return x == std::floor(x) && x >= 0 && x < 0x1p64;
  }
  return false;
}

// The values of a DataArray whose text is [p, end).
std::vector<double> read_values(const VtkArray& a, const std::string& format, size_t header_size,
                                const char* p, const char* end) {
  std::vector<double> v;
  if (format == "ascii") {
    std::string text(p, end);
    const char* q = text.c_str();
    for (;;) {
      while (std::isspace(static_cast<unsigned char>(*q))) ++q;
      if (!*q) break;
      char* stop = nullptr;
      double x = std::strtod(q, &stop);
      if (stop == q) fail("array '" + a.name + "': non-numeric ascii value");
      if (!hold_as(a.number, &x))
        fail("array '" + a.name + "': ascii value " + std::string(q, std::min<const char*>(stop, q + 40)) +
             " is not a " + a.type);
      v.push_back(x);
      q = stop;
    }
    return v;
  }
  if (format != "binary")
    fail("array '" + a.name + "' has format \"" + format + "\" (binary and ascii are read)");
  const std::string bytes = base64_decode(p, end, a.name);
  if (bytes.size() < header_size) fail("array '" + a.name + "': truncated header");
  const uint64_t count =
      header_size == 8 ? load_le<uint64_t>(bytes.data()) : load_le<uint32_t>(bytes.data());
  if (count > bytes.size() - header_size)
    fail("array '" + a.name + "': truncated (its header says " + std::to_string(count) +
         " bytes, it has " + std::to_string(bytes.size() - header_size) + ")");
  const size_t size = number_size(a.number);
  if (count % size != 0)
    fail("array '" + a.name + "': " + std::to_string(count) + " bytes is not a whole number of " +
         a.type + " values");
  v.resize(count / size);
  const char* q = bytes.data() + header_size;
  for (size_t i = 0; i < v.size(); ++i, q += size) v[i] = load_le_number(a.number, q);
  return v;
}

}  // namespace

VtkPiece read_vtk_piece(const std::string& bytes,
                        const std::function<bool(const std::string&)>& read) {
  std::vector<std::string> open;  // the elements enclosing the current position
  VtkPiece piece;
  size_t header_size = 4;  // VTK's default header_type is UInt32
  int pieces = 0;
  bool root = false;
  Tag tag;
  size_t pos = 0;
  while (next_tag(bytes, pos, &tag)) {
    pos = tag.end;
    if (tag.closing) {
      if (open.empty() || open.back() != tag.name)
        fail("</" + tag.name + "> does not close " +
             (open.empty() ? std::string("any element") : "<" + open.back() + ">"));
      open.pop_back();
      continue;
    }
    if (open.empty() && root) fail("a second root element <" + tag.name + ">");
    if (tag.name == "VTKFile") {
      if (!open.empty()) fail("<VTKFile> inside <" + open.back() + ">");
      root = true;
      const std::string* type = tag.attr("type");
      if (!type || *type != "UnstructuredGrid")
        fail("not an unstructured grid (VTKFile type \"" + (type ? *type : "") + "\")");
      const std::string* order = tag.attr("byte_order");
      if (order && *order != "LittleEndian")
        fail("byte_order \"" + *order + "\" (only LittleEndian is read)");
      if (const std::string* h = tag.attr("header_type")) {
        if (*h == "UInt64")
          header_size = 8;
        else if (*h != "UInt32")
          fail("header_type \"" + *h + "\" (UInt32 and UInt64 are read)");
      }
      if (tag.attr("compressor")) fail("compressed VTU is not read (save uncompressed)");
    } else if (!root) {
      fail("the root element is <" + tag.name + ">, not <VTKFile>");
    } else if (tag.name == "Piece") {
      if (++pieces > 1) fail("more than one Piece (not read)");
      const std::string* np = tag.attr("NumberOfPoints");
      if (!np) fail("Piece without NumberOfPoints");
      piece.points = count_attribute(*np, "NumberOfPoints");
      if (const std::string* nc = tag.attr("NumberOfCells"))
        piece.cells = count_attribute(*nc, "NumberOfCells");
    } else if (tag.name == "AppendedData") {
      fail("appended data (not read; save with inline binary or ascii data)");
    } else if (tag.name == "DataArray") {
      if (open.empty()) fail("<DataArray> outside any element");
      VtkArray a;
      a.parent = open.back();
      const std::string* name = tag.attr("Name");
      a.name = name ? *name : "";
      const std::string* type = tag.attr("type");
      if (!type) fail("array '" + a.name + "' has no type");
      const VtkType* t = find_type(*type);
      if (!t) fail("array '" + a.name + "' has unknown type \"" + *type + "\"");
      a.type = t->name;
      a.number = t->number;
      if (const std::string* c = tag.attr("NumberOfComponents"))
        a.components = count_attribute(*c, "NumberOfComponents of '" + a.name + "'");
      if (a.components == 0) fail("array '" + a.name + "' has 0 components");
      if (a.components > kMaxColumns)
        fail("array '" + a.name + "' has " + std::to_string(a.components) +
             " components (at most " + std::to_string(kMaxColumns) + ")");
      if (tag.attr("offset")) fail("array '" + a.name + "' refers to appended data (not read)");
      const std::string* format = tag.attr("format");
      if (!format) fail("array '" + a.name + "' has no format");
      if (!tag.empty) {
        const size_t close = bytes.find('<', pos);
        if (close == std::string::npos || bytes.compare(close, 12, "</DataArray>") != 0)
          fail("array '" + a.name + "' is not closed by </DataArray>");
        if (read(a.parent))
          a.values = read_values(a, *format, header_size, bytes.data() + pos, bytes.data() + close);
        pos = close + 12;
      }
      piece.arrays.push_back(std::move(a));
      continue;  // closed (or empty): nothing to push on `open`
    }
    if (!tag.empty) open.push_back(tag.name);
  }
  if (!root) fail("no <VTKFile> element");
  if (!open.empty()) fail("truncated: <" + open.back() + "> is not closed");
  if (pieces == 0) fail("no Piece");
  return piece;
}

void add_vtk_columns(const VtkArray& a, size_t tuples, const char* what,
                     const std::vector<size_t>* rows, PointTable* t, ColumnNames* names) {
  // Divided, not multiplied: tuples x components can wrap around.
  if (a.values.size() % a.components != 0 || a.values.size() / a.components != tuples)
    fail("array '" + a.name + "' has " + std::to_string(a.values.size()) + " values, expected " +
         std::to_string(tuples) + " " + what + " x " + std::to_string(a.components));
  // Checked before making the names: a long name of many components would make many long ones.
  if (a.name.size() > kMaxColumnName)
    fail("an array name of " + std::to_string(a.name.size()) + " bytes (at most " +
         std::to_string(kMaxColumnName) + ")");
  if (t->names.size() + a.components > kMaxColumns)
    fail("array '" + a.name + "' of " + std::to_string(a.components) +
         " components makes more than " + std::to_string(kMaxColumns) + " columns");
  const std::vector<std::string> cols =
      attribute_columns(a.name, int(a.components), AttributeFormat::Vtu);
  std::string why;
  for (size_t k = 0; k < cols.size(); ++k) {
    if (!names->add(cols[k], &why)) fail("array '" + a.name + "' gives " + why);
    std::vector<double> c(rows ? rows->size() : tuples);
    for (size_t i = 0; i < c.size(); ++i)
      c[i] = a.values[(rows ? (*rows)[i] : i) * a.components + k];
    t->names.push_back(cols[k]);
    t->types.push_back(exact_column_type(a.number));
    t->columns.push_back(std::move(c));
  }
}
void write_vtk_array(std::string* out, const char* indent, const std::string& name,
                     const char* type, size_t components, const std::string& raw) {
  *out += indent;
  *out += "<DataArray type=\"" + std::string(type) + "\" Name=\"" + xml_escape(name) + "\"";
  if (components != 1) *out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  *out += " format=\"binary\">";
  std::string block;
  append_le<uint64_t>(&block, raw.size());
  *out += base64_encode(block + raw);
  *out += "</DataArray>\n";
}

std::string vtk_grid_begin(size_t points, size_t cells) {
  return "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
         "  <UnstructuredGrid>\n"
         "    <Piece NumberOfPoints=\"" +
         std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) + "\">\n";
}

void write_vtk_cells_and_end(std::string* out, const std::string& connectivity,
                             const std::string& offsets, const std::string& types) {
  *out += "      <Cells>\n";
  write_vtk_array(out, "        ", "connectivity", "Int64", 1, connectivity);
  write_vtk_array(out, "        ", "offsets", "Int64", 1, offsets);
  write_vtk_array(out, "        ", "types", "UInt8", 1, types);
  *out +=
      "      </Cells>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n"
      "</VTKFile>\n";
}

// The raw little-endian values of a grouped attribute, component-interleaved.
std::string vtk_attribute_bytes(const PointAttribute& a, size_t n) {
  std::string raw;
  raw.reserve(n * a.components.size() * 8);
  for (size_t i = 0; i < n; ++i)
    for (const std::vector<double>* c : a.components) {
      const double v = c ? (*c)[i] : 0.0;
      if (a.integer)
        append_le(&raw, int32_t(v));
      else if (a.float64)
        append_le(&raw, v);
      else
        append_le(&raw, float(v));
    }
  return raw;
}

const char* vtk_type_name(const PointAttribute& a) {
  return a.integer ? "Int32" : a.float64 ? "Float64" : "Float32";
}

}  // namespace tear
