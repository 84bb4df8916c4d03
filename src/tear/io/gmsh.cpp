// gmsh MSH 4.1 (ASCII and binary) as a VolumeMesh: io/volume_mesh.h says what is kept. The
// layout is gmsh's reference manual's "MSH file format" (version 4.1): in binary, every size_t
// is 8 bytes (data-size 8), every int 4, every double 8, in the byte order of the int 1 that
// follows the format line; a block's node tags come before its coordinates.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "tear/io/endian.h"
#include "tear/io/numbers.h"
#include "tear/io/text_tokens.h"
#include "tear/io/volume_mesh.h"

namespace tear {

namespace {

// gmsh's element types (the manual's list): corner count, dimension, first order or not.
struct MshType {
  int type, nodes, dim;
  bool linear;
  const char* name;
};

const MshType kMshTypes[] = {
    {1, 2, 1, true, "2-node line"},
    {2, 3, 2, true, "3-node triangle"},
    {3, 4, 2, true, "4-node quadrangle"},
    {4, 4, 3, true, "4-node tetrahedron"},
    {5, 8, 3, true, "8-node hexahedron"},
    {6, 6, 3, true, "6-node prism"},
    {7, 5, 3, true, "5-node pyramid"},
    {8, 3, 1, false, "3-node second order line"},
    {9, 6, 2, false, "6-node second order triangle"},
    {10, 9, 2, false, "9-node second order quadrangle"},
    {11, 10, 3, false, "10-node second order tetrahedron"},
    {12, 27, 3, false, "27-node second order hexahedron"},
    {13, 18, 3, false, "18-node second order prism"},
    {14, 14, 3, false, "14-node second order pyramid"},
    {15, 1, 0, true, "1-node point"},
    {16, 8, 2, false, "8-node second order quadrangle"},
    {17, 20, 3, false, "20-node second order hexahedron"},
    {18, 15, 3, false, "15-node second order prism"},
    {19, 13, 3, false, "13-node second order pyramid"},
    {20, 9, 2, false, "9-node third order incomplete triangle"},
    {21, 10, 2, false, "10-node third order triangle"},
    {22, 12, 2, false, "12-node fourth order incomplete triangle"},
    {23, 15, 2, false, "15-node fourth order triangle"},
    {24, 15, 2, false, "15-node fifth order incomplete triangle"},
    {25, 21, 2, false, "21-node fifth order triangle"},
    {26, 4, 1, false, "4-node third order edge"},
    {27, 5, 1, false, "5-node fourth order edge"},
    {28, 6, 1, false, "6-node fifth order edge"},
    {29, 20, 3, false, "20-node third order tetrahedron"},
    {30, 35, 3, false, "35-node fourth order tetrahedron"},
    {31, 56, 3, false, "56-node fifth order tetrahedron"},
};

const MshType* find_msh_type(int type) {
  for (const MshType& t : kMshTypes)
    if (t.type == type) return &t;
  return nullptr;
}

constexpr const char* kRead = "tear reads 4-node tetrahedra (type 4) and 3-node triangles (type 2)";

// A token as it may be shown in a message: at most 40 bytes, unprintable ones as '?'.
std::string shown(std::string_view tok) {
  std::string s(tok.substr(0, 40));
  for (char& c : s)
    if (c < ' ' || c > '~') c = '?';
  return s;
}

class MshReader {
 public:
  explicit MshReader(const std::string& bytes) : bytes_(bytes), text_(bytes) {}

  VolumeMesh read() {
    read_format();
    for (;;) {
      const std::string_view tok = text_.next();
      if (tok.empty()) break;
      if (tok == "$Nodes")
        read_nodes();
      else if (tok == "$Elements")
        read_elements();
      else if (tok[0] == '$' && tok.substr(0, 4) != "$End")
        skip_section(tok);
      else
        fail("unexpected '" + shown(tok) + "' between sections");
    }
    if (!have_nodes_) throw std::runtime_error("gmsh: no $Nodes section");
    if (!have_elements_) throw std::runtime_error("gmsh: no $Elements section");
    if (max_dim_ < 2) throw std::runtime_error("gmsh: no tetrahedra or triangles");
    if (!refused_[max_dim_].empty()) throw std::runtime_error("gmsh: " + refused_[max_dim_]);
    VolumeMesh m;
    m.dim = max_dim_;
    m.nodes = std::move(nodes_);
    m.cells = std::move(max_dim_ == 3 ? tets_ : triangles_);
    check_volume_mesh(m, "gmsh: ");
    return m;
  }

 private:
  // Where the value being read begins: a line in ASCII, a byte offset in binary.
  std::string where() const {
    return binary_ ? "byte " + std::to_string(at_) : "line " + std::to_string(text_.line());
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error("gmsh: " + where() + ": " + why);
  }

  // The next token, which must be there (`what` names it in the error).
  std::string_view token(const char* what) {
    const std::string_view tok = text_.next();
    if (tok.empty()) fail("the file ends where " + std::string(what) + " should be");
    return tok;
  }
  void expect(const char* word) {
    const std::string_view tok = text_.next();
    at_ = text_.pos();
    if (tok != word)
      fail("expected " + std::string(word) + ", found '" + (tok.empty() ? "the end" : shown(tok)) +
           "'");
  }
  template <class T>
  T raw(const char* what) {
    at_ = text_.pos();
    if (text_.remaining() < sizeof(T)) fail("the file ends inside " + std::string(what));
    const char* p = bytes_.data() + text_.pos();
    text_.skip_to(text_.pos() + sizeof(T));
    return little_ ? load_le<T>(p) : load_be<T>(p);
  }
  uint64_t read_size(const char* what) {
    if (binary_) return raw<uint64_t>(what);
    const std::string_view tok = token(what);
    size_t n = 0;
    if (!parse_count(std::string(tok), &n))
      fail("expected " + std::string(what) + ", found '" + shown(tok) + "'");
    return n;
  }
  int read_int(const char* what) {
    if (binary_) return raw<int32_t>(what);
    const std::string_view tok = token(what);
    int64_t v = 0;
    if (!parse_integer(tok, &v) || v < INT32_MIN || v > INT32_MAX)
      fail("expected " + std::string(what) + ", found '" + shown(tok) + "'");
    return int(v);
  }
  double read_double(const char* what) {
    if (binary_) return raw<double>(what);
    const std::string_view tok = token(what);
    double v = 0;
    if (!parse_real(tok, &v))
      fail("expected " + std::string(what) + ", found '" + shown(tok) + "'");
    return v;
  }
  // A count of things of at least `bytes_each` bytes apiece (in the file's encoding), checked
  // against what is left of the file before anything is reserved for them.
  void check_room(uint64_t n, size_t bytes_each, const std::string& what) const {
    // In ASCII the last token needs no separator after it.
    const size_t room = (text_.remaining() + (binary_ ? 0 : 1)) / bytes_each;
    if (n > room)
      fail(std::to_string(n) + " " + what + " do not fit in the " +
           std::to_string(text_.remaining()) + " bytes left (at most " + std::to_string(room) +
           ")");
  }

  void read_format() {
    if (text_.next() != "$MeshFormat") fail("not a gmsh mesh: it does not begin with $MeshFormat");
    const std::string_view version = token("the version");
    if (version != "4.1")
      fail("version " + shown(version) +
           " files are not read; save as MSH 4.1 (gmsh -format msh41)");
    const std::string_view type = token("the file-type");
    if (type != "0" && type != "1") fail("file-type '" + shown(type) + "' (0: ASCII, 1: binary)");
    const std::string_view size = token("the data-size");
    if (size != "8") fail("data-size '" + shown(size) + "' (only 8, a 64-bit size_t, is read)");
    if (type == "1") {
      text_.skip_line();
      binary_ = true;
      at_ = text_.pos();
      if (text_.remaining() < 4) fail("the file ends before the endianness int");
      const char* p = bytes_.data() + text_.pos();
      if (load_le<int32_t>(p) != 1 && load_be<int32_t>(p) != 1)
        fail("the endianness int is not 1 in either byte order");
      little_ = load_le<int32_t>(p) == 1;
      text_.skip_to(text_.pos() + 4);
    }
    expect("$EndMeshFormat");
  }

  void skip_section(std::string_view tok) {
    const std::string end = "$End" + std::string(tok.substr(1));
    const size_t found = bytes_.find(end, text_.pos());
    if (found == std::string::npos) fail(shown(tok) + " is not closed by " + shown(end));
    text_.skip_to(found + end.size());
  }

  void read_nodes() {
    if (have_nodes_) fail("a second $Nodes section (not read)");
    have_nodes_ = true;
    if (binary_) text_.skip_line();  // the binary data begins after the section's name
    const uint64_t blocks = read_size("the number of entity blocks");
    const uint64_t total = read_size("the number of nodes");
    read_size("the smallest node tag");
    read_size("the largest node tag");
    if (total > UINT32_MAX) fail(std::to_string(total) + " nodes (at most 2^32 - 1 are read)");
    check_room(blocks, binary_ ? 20 : 8, "entity blocks");
    for (uint64_t b = 0; b < blocks; ++b) {
      const int dim = read_int("an entity dimension");
      if (dim < 0 || dim > 3) fail("entity dimension " + std::to_string(dim) + " (0 to 3)");
      read_int("an entity tag");
      const int parametric = read_int("the parametric flag");
      if (parametric != 0 && parametric != 1)
        fail("parametric flag " + std::to_string(parametric) + " (0 or 1)");
      const uint64_t n = read_size("the number of nodes in a block");
      const size_t values = 3 + size_t(parametric ? dim : 0);  // x y z, then u v w
      check_room(n, binary_ ? 8 * (1 + values) : 2 * (1 + values), "nodes");
      if (n > total - nodes_.size())
        fail("the entity blocks hold more than the " + std::to_string(total) +
             " nodes of the section's header");
      std::vector<uint64_t> tags(n);
      index_.reserve(index_.size() + n);
      for (uint64_t i = 0; i < n; ++i) {
        tags[i] = read_size("a node tag");
        if (tags[i] == 0) fail("node tag 0 (tags begin at 1)");
        if (!index_.emplace(tags[i], uint32_t(nodes_.size() + i)).second)
          fail("node tag " + std::to_string(tags[i]) + " appears twice");
      }
      for (uint64_t i = 0; i < n; ++i) {
        std::array<double, 3> x;
        for (double& c : x) c = read_double("a coordinate");
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
          fail("node " + std::to_string(tags[i]) + " has a coordinate that is not finite");
        for (size_t k = 3; k < values; ++k) read_double("a parametric coordinate");
        nodes_.push_back(x);
      }
    }
    if (nodes_.size() != total)
      fail("the entity blocks hold " + std::to_string(nodes_.size()) + " nodes, the header says " +
           std::to_string(total));
    expect("$EndNodes");
  }

  void read_elements() {
    if (!have_nodes_) fail("$Elements before $Nodes");
    if (have_elements_) fail("a second $Elements section (not read)");
    have_elements_ = true;
    if (binary_) text_.skip_line();
    const uint64_t blocks = read_size("the number of entity blocks");
    const uint64_t total = read_size("the number of elements");
    read_size("the smallest element tag");
    read_size("the largest element tag");
    check_room(blocks, binary_ ? 20 : 8, "entity blocks");
    uint64_t seen = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const int dim = read_int("an entity dimension");
      read_int("an entity tag");
      const int type = read_int("an element type");
      const MshType* t = find_msh_type(type);
      if (!t) fail("element type " + std::to_string(type) + " (not a gmsh type this reader knows)");
      if (t->dim != dim)
        fail("element type " + std::to_string(type) + " (" + t->name +
             ") in an entity of dimension " + std::to_string(dim));
      const std::string what =
          "element type " + std::to_string(type) + " (" + t->name + ") is not read: " + kRead;
      if (!t->linear && t->dim >= 2) fail(what);
      const uint64_t n = read_size("the number of elements in a block");
      check_room(n, binary_ ? 8 * size_t(1 + t->nodes) : 2 * size_t(1 + t->nodes), "elements");
      if (n > total - seen)
        fail("the entity blocks hold more than the " + std::to_string(total) +
             " elements of the section's header");
      seen += n;
      if (n > 0) max_dim_ = std::max(max_dim_, t->dim);
      const bool keep = type == 4 || type == 2;
      if (!keep && n > 0 && t->dim >= 2 && refused_[t->dim].empty())
        refused_[t->dim] = where() + ": " + what;
      std::vector<std::array<uint32_t, 4>>& cells = type == 4 ? tets_ : triangles_;
      if (keep) cells.reserve(cells.size() + n);
      for (uint64_t e = 0; e < n; ++e) {
        const uint64_t tag = read_size("an element tag");
        std::array<uint32_t, 4> cell{0, 0, 0, 0};
        for (int c = 0; c < t->nodes; ++c) {
          const uint64_t node = read_size("a node tag");
          if (!keep) continue;
          const auto it = index_.find(node);
          if (it == index_.end())
            fail("element " + std::to_string(tag) + " names node " + std::to_string(node) +
                 ", the file has " + std::to_string(nodes_.size()) + " nodes");
          cell[size_t(c)] = it->second;
        }
        if (keep) cells.push_back(cell);
      }
    }
    if (seen != total)
      fail("the entity blocks hold " + std::to_string(seen) + " elements, the header says " +
           std::to_string(total));
    expect("$EndElements");
  }

  const std::string& bytes_;
  TextTokens text_;
  bool binary_ = false, little_ = true;
  size_t at_ = 0;
  bool have_nodes_ = false, have_elements_ = false;
  std::vector<std::array<double, 3>> nodes_;
  std::unordered_map<uint64_t, uint32_t> index_;  // node tag -> node index
  std::vector<std::array<uint32_t, 4>> tets_, triangles_;
  int max_dim_ = -1;
  std::string refused_[4];  // per dimension: why its first refused block is refused, and where
};

}  // namespace

VolumeMesh decode_gmsh(const std::string& bytes) { return MshReader(bytes).read(); }

}  // namespace tear
