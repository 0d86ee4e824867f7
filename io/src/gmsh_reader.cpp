// Gmsh MSH files (load_gmsh). The format is the one Gmsh's reference manual defines (doc/texinfo/gmsh.texi in Gmsh's
// sources): "MSH file format" for 4.1, "MSH file format version 2 (Legacy)" for 2.2; 4.0 differs from 4.1 only in
// the $Nodes and $Elements headers (no min/max tags, entity tag before dimension, a node's tag on its coordinates'
// line), and Gmsh writes it in ASCII only.
//
// Orientation: Gmsh's reference tetrahedron (manual, "Node ordering") has node 0 at the origin and nodes 1, 2, 3 on
// its u, v and w axes, so det[p1 − p0, p2 − p0, p3 − p0] > 0: a tet Gmsh orients positively is positive for
// check_tet_mesh too, and the corners are kept in their order. Tets Gmsh meshed bear this out (the 6 of Gmsh's own
// benchmarks/misc/adaptive_tet10.msh and the 24 of adaptive_tet20.msh all have a positive determinant). A file with
// an inverted tet is refused by check_tet_mesh rather than silently flipped: it is a broken file.
#include "pbd/io/tet_mesh_reader.hpp"

#include "file_bytes.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"
#include "tet_mesh_assembly.hpp"
#include "text_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

namespace pbd {
namespace {

using detail::message;
using detail::shown;

// The element types the manual lists (elementType): nodes per element and dimension. Skipping an element needs its
// node count in binary (and checking a line's length in ASCII), so a type not listed here is refused.
struct ElementType {
  int type;
  int nodes;
  int dim;
  const char* name;
};

constexpr ElementType kElementTypes[] = {
    {1, 2, 1, "2-node line"},           {2, 3, 2, "3-node triangle"},       {3, 4, 2, "4-node quadrangle"},
    {4, 4, 3, "4-node tetrahedron"},    {5, 8, 3, "8-node hexahedron"},     {6, 6, 3, "6-node prism"},
    {7, 5, 3, "5-node pyramid"},        {8, 3, 1, "3-node line"},           {9, 6, 2, "6-node triangle"},
    {10, 9, 2, "9-node quadrangle"},    {11, 10, 3, "10-node tetrahedron"}, {12, 27, 3, "27-node hexahedron"},
    {13, 18, 3, "18-node prism"},       {14, 14, 3, "14-node pyramid"},     {15, 1, 0, "1-node point"},
    {16, 8, 2, "8-node quadrangle"},    {17, 20, 3, "20-node hexahedron"},  {18, 15, 3, "15-node prism"},
    {19, 13, 3, "13-node pyramid"},     {20, 9, 2, "9-node triangle"},      {21, 10, 2, "10-node triangle"},
    {22, 12, 2, "12-node triangle"},    {23, 15, 2, "15-node triangle"},    {24, 15, 2, "15-node triangle"},
    {25, 21, 2, "21-node triangle"},    {26, 4, 1, "4-node line"},          {27, 5, 1, "5-node line"},
    {28, 6, 1, "6-node line"},          {29, 20, 3, "20-node tetrahedron"}, {30, 35, 3, "35-node tetrahedron"},
    {31, 56, 3, "56-node tetrahedron"}, {92, 64, 3, "64-node hexahedron"},  {93, 125, 3, "125-node hexahedron"}};
constexpr int kTet = 4;

constexpr std::size_t kNowhere = std::numeric_limits<std::size_t>::max();

bool is_blank(std::string_view line) { return line.find_first_not_of(" \t\r") == std::string_view::npos; }

std::string_view trimmed(std::string_view line) {
  const std::size_t start = line.find_first_not_of(" \t\r");
  if (start == std::string_view::npos) return {};
  return line.substr(start, line.find_last_not_of(" \t\r") + 1 - start);
}

// Reads one MSH file: the sections up to the first $Elements, collecting nodes (tag, coordinates, where) and tets
// (element tag, node tags, where), then resolves the tags. Positions in the data are byte offsets; a message turns
// one into a line number while the file is still text, and keeps it as a byte offset past the first binary data,
// where lines mean nothing.
class GmshReader {
public:
  GmshReader(std::string_view data, const std::string& source) : data_(data), source_(source) {}

  TetMesh read() {
    read_mesh_format();
    while (!read_section()) section_.clear();
    section_.clear();
    return assemble();
  }

private:
  // --- where: messages ---------------------------------------------------------------------------------------

  std::size_t line_of(std::size_t at) const {
    return 1 + std::size_t(std::count(data_.begin(), data_.begin() + std::ptrdiff_t(at), '\n'));
  }
  bool in_binary(std::size_t at) const { return binary_start_ != kNowhere && at >= binary_start_; }
  std::string where(std::size_t at) const {
    return in_binary(at) ? message("byte ", at) : message("line ", line_of(at));
  }
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    if (in_binary(at))
      throw Error(message(source_, ": byte ", at, section_.empty() ? "" : " in ", section_, ": ", what));
    throw Error(message(source_, ":", line_of(at), ": ", what));
  }

  // --- text ----------------------------------------------------------------------------------------------------

  // The next line (without its "\n" or "\r\n"), starting at `at`; the file must not have ended.
  std::string_view next_line(std::size_t& at) {
    if (pos_ >= data_.size())
      fail(data_.size(), section_.empty() ? std::string("the file ends early") : "the file ends inside " + section_);
    at = pos_;
    const void* nl = std::memchr(data_.data() + pos_, '\n', data_.size() - pos_);
    const std::size_t end = nl ? std::size_t(static_cast<const char*>(nl) - data_.data()) : data_.size();
    pos_ = nl ? end + 1 : end;
    std::string_view line = data_.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
  }

  void skip_blank_lines() {
    while (pos_ < data_.size()) {
      const std::size_t before = pos_;
      std::size_t at = 0;
      if (!is_blank(next_line(at))) {
        pos_ = before;
        return;
      }
    }
  }

  const std::vector<std::string_view>& line_fields(std::size_t& at) {
    detail::split_fields(next_line(at), fields_);
    return fields_;
  }

  // The fields of item i of n `what` (a node, an element, a block header): a line starting with '$' means the
  // section ended before its count did.
  const std::vector<std::string_view>& item_fields(std::size_t& at, std::uint64_t i, std::uint64_t n,
                                                   const char* what) {
    const std::string_view line = next_line(at);
    if (!line.empty() && line[0] == '$')
      fail(at, message(section_, " declares ", n, " ", what, " but has ", i, " (found \"", shown(line), "\")"));
    detail::split_fields(line, fields_);
    return fields_;
  }

  std::int64_t integer(std::string_view field, std::size_t at, const char* what) const {
    const auto v = detail::integer_field(field);
    if (!v) fail(at, message(what, " \"", shown(field), "\" is not an integer"));
    return *v;
  }
  std::uint64_t count(std::string_view field, std::size_t at, const char* what) const {
    const std::int64_t v = integer(field, at, what);
    if (v < 0) fail(at, message(what, " ", v, " is negative"));
    return std::uint64_t(v);
  }
  std::uint64_t tag(std::string_view field, std::size_t at, const char* what) const {
    const std::int64_t v = integer(field, at, what);
    if (v <= 0) fail(at, message(what, " ", v, " is not positive (tags start at 1)"));
    return std::uint64_t(v);
  }
  double coordinate(std::string_view field, std::size_t at) const {
    const auto v = detail::number_field(field);
    if (!v) fail(at, message("coordinate \"", shown(field), "\" is not a number"));
    if (!std::isfinite(*v)) fail(at, message("coordinate \"", shown(field), "\" is not a finite number"));
    return *v;
  }

  // Refuses `n` items of at least `bytes_each` bytes that the rest of the file cannot hold, before room for them is
  // made: a corrupt count must not become a huge allocation.
  void check_room(std::uint64_t n, std::size_t bytes_each, std::size_t at, const char* what) const {
    const std::size_t left = data_.size() - pos_;
    if (n > left / bytes_each)
      fail(at,
           message(n, " ", what, " cannot fit in the ", left, " bytes left (each takes at least ", bytes_each, ")"));
  }

  void expect_end(std::string_view end, const std::string& after) {
    std::size_t at = 0;
    const std::string_view line = next_line(at);
    if (trimmed(line) != end) fail(at, message("expected ", end, " after ", after, ", found \"", shown(line), "\""));
  }

  void skip_section(std::string_view name, std::size_t at) {
    // Also in a binary file, where a binary section ($PartitionedEntities, $Periodic...) could only be mistaken for
    // its end if its data held the bytes "\n$End<name>" themselves.
    const std::string end = "$End" + std::string(name.substr(1));
    while (pos_ < data_.size()) {
      std::size_t line_at = 0;
      if (trimmed(next_line(line_at)) == end) return;
    }
    fail(at, message(shown(name), " has no ", shown(end), " line"));
  }

  // --- binary --------------------------------------------------------------------------------------------------

  void start_binary() { binary_start_ = std::min(binary_start_, pos_); }

  void need(std::size_t bytes) const {
    if (bytes > data_.size() - pos_)
      fail(pos_,
           message("the binary data end early: ", bytes, " bytes are needed, ", data_.size() - pos_, " are left"));
  }
  void skip(std::uint64_t n, std::size_t bytes_each) {
    check_room(n, bytes_each, pos_, "values");
    pos_ += std::size_t(n) * bytes_each;
  }

  template <class T>
  T value() {
    need(sizeof(T));
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, data_.data() + pos_, sizeof(T));
    if (swap_) std::reverse(bytes, bytes + sizeof(T));
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::int32_t binary_int() { return value<std::int32_t>(); }
  std::uint64_t binary_size() { return size_t_bytes_ == 4 ? value<std::uint32_t>() : value<std::uint64_t>(); }
  double binary_double() { return value<double>(); }
  std::uint64_t binary_tag(const char* what) {
    const std::size_t at = pos_;
    const std::uint64_t t = binary_size();
    if (t == 0 || t > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
      fail(at, message(what, " ", t, " is not a tag (tags start at 1)"));
    return t;
  }

  // Gmsh ends binary data with "\n", then the $End line.
  void expect_binary_end(std::string_view end) {
    while (pos_ < data_.size() && (data_[pos_] == '\n' || data_[pos_] == '\r')) ++pos_;
    std::size_t at = pos_;
    const std::string_view line = pos_ < data_.size() ? next_line(at) : std::string_view();
    if (trimmed(line) != end)
      fail(at, message("expected ", end, " where the binary data end, found \"", shown(line), "\""));
  }

  // --- sections ----------------------------------------------------------------------------------------------

  // Reads or skips the next section; true once it was $Elements, after which nothing more is read (periodicity,
  // post-processing data: not needed).
  bool read_section() {
    skip_blank_lines();
    if (pos_ == data_.size()) fail(pos_, "the file has no $Elements section");
    std::size_t at = 0;
    const std::string_view name = trimmed(next_line(at));
    const bool header = name.size() > 1 && name[0] == '$' && name.substr(0, 4) != "$End";
    if (!header) fail(at, message("expected a section ($Nodes, $Elements, ...), found \"", shown(name), "\""));
    section_ = shown(name);
    if (name == "$Nodes") {
      read_nodes();
      have_nodes_ = true;
    } else if (name == "$Elements") {
      if (!have_nodes_) fail(at, "$Elements comes before $Nodes (the format defines nodes first)");
      read_elements();
      return true;
    } else if (name == "$Entities" && binary_ && major_ == 4) {
      skip_binary_entities();
    } else {
      skip_section(name, at);
    }
    return false;
  }

  // --- $MeshFormat ---------------------------------------------------------------------------------------------

  void read_mesh_format() {
    std::size_t at = 0;
    if (trimmed(next_line(at)) != "$MeshFormat") fail(at, "not an MSH file: the first line is not $MeshFormat");
    section_ = "$MeshFormat";
    read_format_line();
    if (binary_) {
      read_endianness_check();
      expect_binary_end("$EndMeshFormat");
    } else {
      // An ASCII file is text throughout, the sections after $Elements (not read) included.
      if (const auto nul = detail::nul_byte(data_))
        throw Error(message(source_, ":", nul->line, ": a NUL byte at column ", nul->column, " (not a text file)"));
      expect_end("$EndMeshFormat", "the format line");
    }
  }

  // "version file-type data-size"
  void read_format_line() {
    std::size_t at = 0;
    const auto& f = line_fields(at);
    if (f.size() != 3) fail(at, message("expected version, file-type and data-size, found ", f.size(), " values"));
    const auto version = detail::number_field(f[0]);
    if (version && (*version == 2.0 || *version == 2.1 || *version == 2.2)) {
      major_ = 2;
    } else if (version && (*version == 4.0 || *version == 4.1)) {
      major_ = 4;
      minor_ = *version == 4.1 ? 1 : 0;
    } else {
      fail(at, message("MSH version ", shown(f[0]),
                       " is not supported; versions 2.2 and 4.1 are (and 2.0, 2.1 and, in ASCII, 4.0)"));
    }
    const std::int64_t type = integer(f[1], at, "file-type");
    if (type != 0 && type != 1) fail(at, message("file-type ", type, " is neither 0 (ASCII) nor 1 (binary)"));
    binary_ = type == 1;
    const std::int64_t data_size = integer(f[2], at, "data-size");
    if (major_ == 2 && data_size != 8)
      fail(at, message("data-size ", data_size, ": MSH 2 files hold 8-byte doubles (data-size 8)"));
    if (major_ == 4 && binary_ && minor_ == 0)
      fail(at, "binary MSH 4.0 is not supported (Gmsh writes version 4.0 in ASCII only); save as 4.1");
    if (major_ == 4 && binary_ && data_size != 4 && data_size != 8)
      fail(at, message("data-size ", data_size, " is not a size of size_t this reader takes (4 or 8)"));
    if (major_ == 4 && binary_) size_t_bytes_ = std::size_t(data_size);
  }

  // The int 1, written in binary where the file was: read as 1 in this machine's byte order or in the other one.
  void read_endianness_check() {
    start_binary();
    const std::size_t at = pos_;
    const std::int32_t one = binary_int();
    if (one == 1) return;
    swap_ = true;
    pos_ = at;
    if (binary_int() != 1) fail(at, message("the endianness check reads ", one, ", not 1 (in either byte order)"));
  }

  // --- nodes ---------------------------------------------------------------------------------------------------

  void reserve_nodes(std::uint64_t n) {
    node_tags_.reserve(node_tags_.size() + std::size_t(n));
    node_at_.reserve(node_at_.size() + std::size_t(n));
    xyz_.reserve(xyz_.size() + 3 * std::size_t(n));
  }
  void add_node_tag(std::uint64_t t, std::size_t at) {
    node_tags_.push_back(t);
    node_at_.push_back(at);
  }

  void read_nodes() {
    if (major_ == 2)
      binary_ ? nodes_v2_binary() : nodes_v2_ascii();
    else
      binary_ ? nodes_v4_binary() : nodes_v4_ascii();
  }

  std::uint64_t v2_count(const char* what) {
    std::size_t at = 0;
    const auto& f = line_fields(at);
    if (f.size() != 1) fail(at, message(section_, " starts with the number of ", what, " alone on its line"));
    const std::uint64_t n = count(f[0], at, message("the number of ", what).c_str());
    check_room(n, binary_ ? 8 : 4, at, what);
    return n;
  }

  void nodes_v2_ascii() {
    const std::uint64_t n = v2_count("nodes");
    reserve_nodes(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      std::size_t at = 0;
      const auto& f = item_fields(at, i, n, "nodes");
      if (f.size() != 4) fail(at, message("a node is a tag and 3 coordinates; this line has ", f.size(), " values"));
      add_node_tag(tag(f[0], at, "node tag"), at);
      for (int d = 1; d <= 3; ++d) xyz_.push_back(coordinate(f[std::size_t(d)], at));
    }
    expect_end("$EndNodes", message("the ", n, " nodes the section declares"));
  }

  void add_binary_coordinates(std::size_t at, std::uint64_t t, int extra) {
    double p[3];
    for (double& c : p) c = binary_double();
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      fail(at, message("node ", t, " has a non-finite coordinate (", p[0], ", ", p[1], ", ", p[2], ")"));
    xyz_.insert(xyz_.end(), p, p + 3);
    pos_ += 8 * std::size_t(extra);  // parametric coordinates: not needed (the block was checked to hold them)
  }

  void nodes_v2_binary() {
    const std::uint64_t n = v2_count("nodes");
    start_binary();
    check_room(n, 4 + 3 * 8, pos_, "nodes");
    reserve_nodes(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::size_t at = pos_;
      const std::int32_t t = binary_int();
      if (t <= 0) fail(at, message("node tag ", t, " is not positive (tags start at 1)"));
      add_node_tag(std::uint64_t(t), at);
      add_binary_coordinates(at, std::uint64_t(t), 0);
    }
    expect_binary_end("$EndNodes");
  }

  // Dimension and parametric flag of a version 4 node block: the number of values after x, y, z.
  int parametric_values(std::int64_t dim, std::int64_t parametric, std::size_t at) const {
    if (dim < 0 || dim > 3) fail(at, message("entity dimension ", dim, " is not 0, 1, 2 or 3"));
    if (parametric != 0 && parametric != 1) fail(at, message("parametric flag ", parametric, " is not 0 or 1"));
    return parametric ? int(dim) : 0;
  }

  void nodes_v4_ascii() {
    std::size_t header_at = 0;
    const auto& h = line_fields(header_at);
    const std::size_t header_size = minor_ == 1 ? 4 : 2;
    if (h.size() != header_size)
      fail(header_at, message("the $Nodes header is ", header_size, " values; this line has ", h.size()));
    const std::uint64_t blocks = count(h[0], header_at, "numEntityBlocks");
    const std::uint64_t total = count(h[1], header_at, "numNodes");
    if (minor_ == 1) {  // minNodeTag and maxNodeTag: checked, not needed
      count(h[2], header_at, "minNodeTag");
      count(h[3], header_at, "maxNodeTag");
    }
    check_room(blocks, 8, header_at, "node blocks");
    check_room(total, 8, header_at, "nodes");
    reserve_nodes(total);
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      std::size_t at = 0;
      const auto& f = item_fields(at, b, blocks, "node blocks");
      if (f.size() != 4) fail(at, message("a node block header is 4 values; this line has ", f.size()));
      const std::int64_t dim = integer(f[minor_ == 1 ? 0 : 1], at, "entityDim");
      const int extra = parametric_values(dim, integer(f[2], at, "parametric"), at);
      const std::uint64_t n = count(f[3], at, "numNodesInBlock");
      if (n > total - seen) fail(at, message("the blocks hold more than the ", total, " nodes the header declares"));
      if (minor_ == 1)
        node_block_v41_ascii(n, extra);
      else
        node_block_v40_ascii(n, extra);
      seen += n;
    }
    if (seen != total) fail(header_at, message("the header declares ", total, " nodes; its blocks hold ", seen));
    expect_end("$EndNodes", message("the ", blocks, " node blocks the header declares"));
  }

  // 4.1: the block's tags, one a line, then its coordinates, one node a line.
  void node_block_v41_ascii(std::uint64_t n, int extra) {
    for (std::uint64_t i = 0; i < n; ++i) {
      std::size_t at = 0;
      const auto& f = item_fields(at, i, n, "node tags in this block");
      if (f.size() != 1) fail(at, message("a node tag is alone on its line; this line has ", f.size(), " values"));
      add_node_tag(tag(f[0], at, "node tag"), at);
    }
    for (std::uint64_t i = 0; i < n; ++i) {
      std::size_t at = 0;
      const auto& f = item_fields(at, i, n, "node coordinates in this block");
      if (f.size() != std::size_t(3 + extra))
        fail(at, message("a node's coordinates are ", 3 + extra, " values in this block; this line has ", f.size()));
      for (int d = 0; d < 3; ++d) xyz_.push_back(coordinate(f[std::size_t(d)], at));
    }
  }

  // 4.0: one node a line, its tag first.
  void node_block_v40_ascii(std::uint64_t n, int extra) {
    for (std::uint64_t i = 0; i < n; ++i) {
      std::size_t at = 0;
      const auto& f = item_fields(at, i, n, "nodes in this block");
      if (f.size() != std::size_t(4 + extra))
        fail(at, message("a node is a tag and ", 3 + extra, " coordinates in this block; this line has ", f.size(),
                         " values"));
      add_node_tag(tag(f[0], at, "node tag"), at);
      for (int d = 1; d <= 3; ++d) xyz_.push_back(coordinate(f[std::size_t(d)], at));
    }
  }

  void nodes_v4_binary() {
    start_binary();
    const std::size_t header_at = pos_;
    const std::uint64_t blocks = binary_size(), total = binary_size();
    binary_size();  // minNodeTag and maxNodeTag: not needed
    binary_size();
    check_room(blocks, 12 + size_t_bytes_, header_at, "node blocks");
    check_room(total, size_t_bytes_ + 24, header_at, "nodes");
    reserve_nodes(total);
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::size_t at = pos_;
      const std::int32_t dim = binary_int();
      binary_int();  // entityTag
      const int extra = parametric_values(dim, binary_int(), at);
      const std::uint64_t n = binary_size();
      if (n > total - seen) fail(at, message("the blocks hold more than the ", total, " nodes the header declares"));
      need(std::size_t(n) * (size_t_bytes_ + 8 * std::size_t(3 + extra)));  // n is bounded by check_room above
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::size_t tag_at = pos_;
        add_node_tag(binary_tag("node tag"), tag_at);
      }
      const std::size_t first = node_tags_.size() - std::size_t(n);
      for (std::uint64_t i = 0; i < n; ++i) add_binary_coordinates(pos_, node_tags_[first + i], extra);
      seen += n;
    }
    if (seen != total) fail(header_at, message("the header declares ", total, " nodes; its blocks hold ", seen));
    expect_binary_end("$EndNodes");
  }

  // --- elements ------------------------------------------------------------------------------------------------

  const ElementType& element_type(std::int64_t type, std::size_t at) const {
    for (const auto& t : kElementTypes)
      if (t.type == type) {
        if (t.dim == 3 && t.type != kTet)
          fail(at, message("element type ", type, " (", t.name,
                           ") is a volume element, and only 4-node tetrahedra (type 4) are read"));
        return t;
      }
    fail(at, message("element type ", type, " is not one this reader knows"));
  }

  void add_tet(std::uint64_t element, const std::array<std::uint64_t, 4>& nodes, std::size_t at) {
    tet_tags_.push_back(nodes);
    tet_element_.push_back(element);
    tet_at_.push_back(at);
  }

  void read_elements() {
    if (major_ == 2)
      binary_ ? elements_v2_binary() : elements_v2_ascii();
    else
      binary_ ? elements_v4_binary() : elements_v4_ascii();
  }

  void elements_v2_ascii() {
    const std::uint64_t n = v2_count("elements");
    for (std::uint64_t i = 0; i < n; ++i) {
      std::size_t at = 0;
      const auto& f = item_fields(at, i, n, "elements");
      if (f.size() < 3)
        fail(at, message("an element is a tag, a type, a number of tags, its tags and its nodes; this line has ",
                         f.size(), " values"));
      const std::uint64_t element = tag(f[0], at, "element tag");
      const ElementType& type = element_type(integer(f[1], at, "element type"), at);
      const std::uint64_t tags = count(f[2], at, "number-of-tags");
      if (tags > f.size() || f.size() != 3 + tags + std::size_t(type.nodes))
        fail(at, message("a ", type.name, " with ", tags, " tags is ", 3 + tags + std::uint64_t(type.nodes),
                         " values; this line has ", f.size()));
      if (type.type == kTet) {
        std::array<std::uint64_t, 4> nodes;
        for (std::size_t k = 0; k < 4; ++k) nodes[k] = tag(f[3 + std::size_t(tags) + k], at, "node tag");
        add_tet(element, nodes, at);
      }
    }
    expect_end("$EndElements", message("the ", n, " elements the section declares"));
  }

  void elements_v2_binary() {
    const std::uint64_t n = v2_count("elements");
    start_binary();
    for (std::uint64_t seen = 0; seen < n;) {
      // A header (type, elements that follow, tags each), then those elements: tag, tags, nodes, all ints.
      const std::size_t at = pos_;
      const ElementType& type = element_type(binary_int(), at);
      const std::int32_t follow = binary_int(), tags = binary_int();
      if (follow <= 0 || std::uint64_t(follow) > n - seen)
        fail(at, message("an element header announces ", follow, " elements; ", n - seen, " of the ", n,
                         " the section declares are left"));
      if (tags < 0) fail(at, message("an element header announces ", tags, " tags"));
      const std::size_t ints = 1 + std::size_t(tags) + std::size_t(type.nodes);
      check_room(std::uint64_t(follow), 4 * ints, at, "elements");
      for (std::int32_t e = 0; e < follow; ++e) {
        const std::size_t element_at = pos_;
        const std::int32_t element = binary_int();
        if (element <= 0) fail(element_at, message("element tag ", element, " is not positive (tags start at 1)"));
        pos_ += 4 * std::size_t(tags);
        if (type.type != kTet) {
          pos_ += 4 * std::size_t(type.nodes);
          continue;
        }
        std::array<std::uint64_t, 4> nodes;
        for (auto& v : nodes) {
          const std::int32_t t = binary_int();
          if (t <= 0) fail(element_at, message("element ", element, " names node tag ", t, ", which is not positive"));
          v = std::uint64_t(t);
        }
        add_tet(std::uint64_t(element), nodes, element_at);
      }
      seen += std::uint64_t(follow);
    }
    expect_binary_end("$EndElements");
  }

  void elements_v4_ascii() {
    std::size_t header_at = 0;
    const auto& h = line_fields(header_at);
    const std::size_t header_size = minor_ == 1 ? 4 : 2;
    if (h.size() != header_size)
      fail(header_at, message("the $Elements header is ", header_size, " values; this line has ", h.size()));
    const std::uint64_t blocks = count(h[0], header_at, "numEntityBlocks");
    const std::uint64_t total = count(h[1], header_at, "numElements");
    if (minor_ == 1) {  // minElementTag and maxElementTag: checked, not needed
      count(h[2], header_at, "minElementTag");
      count(h[3], header_at, "maxElementTag");
    }
    check_room(blocks, 8, header_at, "element blocks");
    check_room(total, 4, header_at, "elements");
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      std::size_t at = 0;
      const auto& f = item_fields(at, b, blocks, "element blocks");
      if (f.size() != 4) fail(at, message("an element block header is 4 values; this line has ", f.size()));
      const ElementType& type = element_type(integer(f[2], at, "elementType"), at);
      const std::uint64_t n = count(f[3], at, "numElementsInBlock");
      if (n > total - seen) fail(at, message("the blocks hold more than the ", total, " elements the header declares"));
      for (std::uint64_t i = 0; i < n; ++i) {
        const auto& g = item_fields(at, i, n, "elements in this block");
        if (g.size() != std::size_t(1 + type.nodes))
          fail(at, message("a ", type.name, " is a tag and ", type.nodes, " node tags; this line has ", g.size(),
                           " values"));
        const std::uint64_t element = tag(g[0], at, "element tag");
        if (type.type != kTet) continue;
        std::array<std::uint64_t, 4> nodes;
        for (std::size_t k = 0; k < 4; ++k) nodes[k] = tag(g[1 + k], at, "node tag");
        add_tet(element, nodes, at);
      }
      seen += n;
    }
    if (seen != total) fail(header_at, message("the header declares ", total, " elements; its blocks hold ", seen));
    expect_end("$EndElements", message("the ", blocks, " element blocks the header declares"));
  }

  void elements_v4_binary() {
    start_binary();
    const std::size_t header_at = pos_;
    const std::uint64_t blocks = binary_size(), total = binary_size();
    binary_size();  // minElementTag and maxElementTag: not needed
    binary_size();
    check_room(blocks, 12 + size_t_bytes_, header_at, "element blocks");
    check_room(total, 2 * size_t_bytes_, header_at, "elements");
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::size_t at = pos_;
      binary_int();  // entityDim
      binary_int();  // entityTag
      const ElementType& type = element_type(binary_int(), at);
      const std::uint64_t n = binary_size();
      if (n > total - seen) fail(at, message("the blocks hold more than the ", total, " elements the header declares"));
      need(std::size_t(n) * (1 + std::size_t(type.nodes)) * size_t_bytes_);  // n is bounded by check_room above
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::size_t element_at = pos_;
        const std::uint64_t element = binary_tag("element tag");
        if (type.type != kTet) {
          pos_ += std::size_t(type.nodes) * size_t_bytes_;
          continue;
        }
        std::array<std::uint64_t, 4> nodes;
        for (auto& v : nodes) v = binary_tag("node tag");
        add_tet(element, nodes, element_at);
      }
      seen += n;
    }
    if (seen != total) fail(header_at, message("the header declares ", total, " elements; its blocks hold ", seen));
    expect_binary_end("$EndElements");
  }

  // --- $Entities (binary 4.1) ----------------------------------------------------------------------------------

  // Read through by its layout, as binary data cannot be searched for $EndEntities: points (tag, x, y, z,
  // physical tags), then curves, surfaces and volumes (tag, bounding box, physical tags, bounding entities).
  void skip_binary_entities() {
    start_binary();
    const std::size_t at = pos_;
    std::uint64_t counts[4];
    for (auto& c : counts) c = binary_size();
    for (int dim = 0; dim < 4; ++dim) {
      check_room(counts[dim], 4 + 24 + size_t_bytes_, at, "entities");
      for (std::uint64_t e = 0; e < counts[dim]; ++e) {
        skip(1, 4);                           // tag
        skip(dim == 0 ? 3 : 6, 8);            // point, or bounding box
        skip(binary_size(), 4);               // physical tags
        if (dim > 0) skip(binary_size(), 4);  // bounding entities
      }
    }
    expect_binary_end("$EndEntities");
  }

  // --- the mesh ------------------------------------------------------------------------------------------------

  TetMesh assemble() const {
    if (tet_tags_.empty()) throw Error(message(source_, ": the file has no 4-node tetrahedra (element type 4)"));
    // Node tags to indices by sorting (tag, index): tags may be sparse up to 2^63, and a sorted table is smaller
    // than a hash map. Equal tags sort by index, so the later of two is the second.
    std::vector<std::pair<std::uint64_t, Index>> by_tag(node_tags_.size());
    for (std::size_t i = 0; i < node_tags_.size(); ++i) by_tag[i] = {node_tags_[i], Index(i)};
    std::sort(by_tag.begin(), by_tag.end());
    std::size_t twice = kNowhere, first = 0;
    for (std::size_t i = 1; i < by_tag.size(); ++i)
      if (by_tag[i].first == by_tag[i - 1].first && (twice == kNowhere || by_tag[i].second < twice)) {
        twice = by_tag[i].second;
        first = by_tag[i - 1].second;
      }
    if (twice != kNowhere)
      fail(node_at_[twice],
           message("node tag ", node_tags_[twice], " appears twice (first at ", where(node_at_[first]), ")"));
    std::vector<std::array<Index, 4>> tets(tet_tags_.size());
    for (std::size_t t = 0; t < tets.size(); ++t)
      for (std::size_t k = 0; k < 4; ++k) {
        const std::uint64_t node = tet_tags_[t][k];
        const auto it = std::lower_bound(by_tag.begin(), by_tag.end(), std::pair<std::uint64_t, Index>(node, 0));
        if (it == by_tag.end() || it->first != node)
          fail(tet_at_[t], message("element ", tet_element_[t], " names node ", node, ", which $Nodes does not have"));
        tets[t][k] = it->second;
      }
    TetMesh mesh = detail::keep_used_nodes(xyz_, tets);
    detail::check_read_tet_mesh(
        mesh, source_, [&](std::size_t t) { return message("element ", tet_element_[t], " at ", where(tet_at_[t])); });
    return mesh;
  }

  std::string_view data_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t binary_start_ = kNowhere;  // the first binary byte: positions from there on are not in lines
  std::string section_;                  // the section being read, for messages
  std::vector<std::string_view> fields_;

  int major_ = 0, minor_ = 0;
  bool binary_ = false, swap_ = false;
  bool have_nodes_ = false;       // a $Nodes section was read
  std::size_t size_t_bytes_ = 8;  // data-size of version 4: sizeof(size_t) where the file was written

  std::vector<std::uint64_t> node_tags_;                // in file order
  std::vector<std::size_t> node_at_;                    // where each node (its tag) is
  std::vector<double> xyz_;                             // 3 coordinates per node
  std::vector<std::array<std::uint64_t, 4>> tet_tags_;  // node tags of each tet
  std::vector<std::uint64_t> tet_element_;              // its element tag
  std::vector<std::size_t> tet_at_;                     // where it is
};

}  // namespace

TetMesh parse_gmsh(std::string_view bytes, const std::string& source) {
  if (bytes.empty()) throw Error(source + ": the file is empty (0 bytes)");
  if (bytes.size() > kMaxTetMeshBytes)
    throw Error(
        message(source, ": ", bytes.size(), " bytes, more than the ", kMaxTetMeshBytes, " a mesh file may have"));
  return GmshReader(bytes, source).read();
}

TetMesh load_gmsh(const std::filesystem::path& file) {
  const detail::FileBytes bytes = detail::read_file_bytes(file, "Gmsh file", kMaxTetMeshBytes);
  return parse_gmsh(bytes.view(), file.string());
}

}  // namespace pbd
