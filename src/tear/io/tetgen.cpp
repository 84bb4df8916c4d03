// TetGen's (and Triangle's) .node and .ele files as a VolumeMesh: io/volume_mesh.h says what is
// kept. The layouts are the two programs' file format pages: a first line of counts, then one
// record per node or element, '#' beginning a comment anywhere.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "tear/io/numbers.h"
#include "tear/io/text_tokens.h"
#include "tear/io/volume_mesh.h"

namespace tear {

namespace {

class TetgenFile {
 public:
  TetgenFile(const std::string& text, const std::string& name) : text_(text, true), name_(name) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(name_ + ": line " + std::to_string(text_.line()) + ": " + why);
  }
  std::string_view token(const char* what) {
    const std::string_view tok = text_.next();
    if (tok.empty()) fail("the file ends where " + std::string(what) + " should be");
    return tok;
  }
  size_t count(const char* what) {
    const std::string_view tok = token(what);
    size_t n = 0;
    if (!parse_count(std::string(tok), &n))
      fail("expected " + std::string(what) + ", found '" + std::string(tok.substr(0, 40)) + "'");
    return n;
  }
  int64_t integer(const char* what) {
    const std::string_view tok = token(what);
    int64_t v = 0;
    if (!parse_integer(tok, &v))
      fail("expected " + std::string(what) + ", found '" + std::string(tok.substr(0, 40)) + "'");
    return v;
  }
  double real(const char* what) {
    const std::string_view tok = token(what);
    double v = 0;
    if (!parse_real(tok, &v) || !std::isfinite(v))
      fail("expected " + std::string(what) + ", found '" + std::string(tok.substr(0, 40)) + "'");
    return v;
  }
  void skip(size_t n, const char* what) {
    for (size_t i = 0; i < n; ++i) token(what);
  }
  // `n` records of `tokens` tokens each must fit in what is left (a token and its separator
  // take at least 2 bytes, the last one 1) before anything is reserved for them.
  void check_room(size_t n, size_t tokens, const char* what) const {
    const size_t room = (text_.remaining() + 1) / 2 / tokens;
    if (n > room)
      fail(std::to_string(n) + " " + what + " do not fit in the " +
           std::to_string(text_.remaining()) + " bytes left (at most " + std::to_string(room) +
           ")");
  }
  void expect_end(size_t n, const char* what) {
    if (!text_.at_end())
      fail("more data after the " + std::to_string(n) + " " + what + " of the first line");
  }

 private:
  TextTokens text_;
  std::string name_;
};

}  // namespace

VolumeMesh decode_tetgen(const std::string& node_text, const std::string& ele_text,
                         const std::string& node_name, const std::string& ele_name) {
  VolumeMesh m;
  TetgenFile node(node_text, node_name);
  const size_t n = node.count("the number of nodes");
  if (n == 0) node.fail("0 nodes (nodes kept in a .poly file are not read)");
  if (n > UINT32_MAX) node.fail(std::to_string(n) + " nodes (at most 2^32 - 1 are read)");
  const size_t node_dim = node.count("the dimension");
  if (node_dim != 2 && node_dim != 3)
    node.fail("dimension " + std::to_string(node_dim) + " (2 or 3)");
  const size_t attributes = node.count("the number of attributes");
  const size_t markers = node.count("the number of boundary markers");
  if (markers > 1) node.fail(std::to_string(markers) + " boundary markers (0 or 1)");
  node.check_room(1, attributes + 1, "attributes");  // before attributes enter a product
  node.check_room(n, 1 + node_dim + attributes + markers, "nodes");
  m.nodes.reserve(n);
  int64_t base = 0;
  for (size_t i = 0; i < n; ++i) {
    const int64_t index = node.integer("a node index");
    if (i == 0 && index != 0 && index != 1)
      node.fail("the first node's index is " + std::to_string(index) + " (0 or 1)");
    if (i == 0) base = index;
    if (index != base + int64_t(i))
      node.fail("node " + std::to_string(i + 1) + " has index " + std::to_string(index) +
                ", expected " + std::to_string(base + int64_t(i)) +
                " (nodes are numbered consecutively)");
    std::array<double, 3> x{0, 0, 0};
    for (size_t k = 0; k < node_dim; ++k) x[k] = node.real("a coordinate");
    node.skip(attributes + markers, "an attribute or marker");
    m.nodes.push_back(x);
  }
  node.expect_end(n, "nodes");

  TetgenFile ele(ele_text, ele_name);
  const size_t cells = ele.count("the number of elements");
  const size_t corners = ele.count("the number of nodes per element");
  if (corners == 10 || corners == 6)
    ele.fail(std::to_string(corners) +
             "-node (second order) elements are not read: tear reads 4-node tetrahedra and "
             "3-node triangles");
  if (corners != 4 && corners != 3)
    ele.fail(std::to_string(corners) + " nodes per element (4: tetrahedra, 3: triangles)");
  if (corners == 4 && node_dim == 2) ele.fail("tetrahedra of 2D nodes");
  const size_t ele_attributes = ele.count("the number of attributes");
  ele.check_room(1, ele_attributes + 1, "attributes");
  ele.check_room(cells, 1 + corners + ele_attributes, "elements");
  m.dim = corners == 4 ? 3 : 2;
  m.cells.reserve(cells);
  for (size_t e = 0; e < cells; ++e) {
    const int64_t index = ele.integer("an element index");
    std::array<uint32_t, 4> cell{0, 0, 0, 0};
    for (size_t c = 0; c < corners; ++c) {
      const int64_t v = ele.integer("a node index");
      if (v < base || v - base >= int64_t(n))
        ele.fail("element " + std::to_string(index) + " names node " + std::to_string(v) +
                 ", the .node file has " + std::to_string(n) + " nodes numbered from " +
                 std::to_string(base));
      cell[c] = uint32_t(v - base);
    }
    ele.skip(ele_attributes, "an attribute");
    m.cells.push_back(cell);
  }
  ele.expect_end(cells, "elements");
  check_volume_mesh(m, ele_name + ": ");
  return m;
}

VolumeMesh decode_tetgen(const std::string& node_text, const std::string& ele_text) {
  return decode_tetgen(node_text, ele_text, "tetgen .node", "tetgen .ele");
}

}  // namespace tear
