// TetGen .node and .ele files (load_tetgen), as TetGen's manual defines them (version 1.5, section 5.2, ".node files"
// and ".ele files").
//
// Orientation: TetGen keeps every tet (p0, p1, p2, p3) with orient3d(p0, p1, p2, p3) < 0, orient3d being Shewchuk's
// predicate det[p0 − p3, p1 − p3, p2 − p3] (positive when p3 is below the plane of p0, p1, p2, "below" being where
// they are seen clockwise). Its mesh check, tetgenmesh::checkmesh in tetgen.cxx (1.5.0), reports a tet with
// orient3d ≥ 0 as "Inverted" or "Degenerated", and its .ele writer (outelements) writes the corners in the order it
// keeps them. As det[p0 − p3, p1 − p3, p2 − p3] = −det[p1 − p0, p2 − p0, p3 − p0], TetGen's orientation is this
// library's: the corners are kept in their order. (The manual's .ele page says only "The first four nodes are the
// corner vertices", with a figure.) Meshes tetgen 1.5.0 made bear this out: the 6 tets of a cube's 8 corners, the 672
// of its own example.poly meshed with -pq, all have det[p1 − p0, p2 − p0, p3 − p0] > 0. A file with an inverted tet
// is refused by check_tet_mesh rather than silently flipped: it is a broken file.
#include "pbd/io/tet_mesh_reader.hpp"

#include "file_bytes.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"
#include "tet_mesh_assembly.hpp"
#include "text_fields.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

namespace pbd {
namespace {

using detail::message;
using detail::shown;

// The lines of a TetGen file that hold data: a comment runs from '#' to the end of its line, and blank lines are
// skipped. Messages name the file and the line read last.
class TetgenText {
public:
  TetgenText(std::string_view text, const std::string& source) : text_(text), source_(source) {
    if (text.empty()) throw Error(source + ": the file is empty (0 bytes)");
    if (text.size() > kMaxTetMeshBytes)
      throw Error(
          message(source, ": ", text.size(), " bytes, more than the ", kMaxTetMeshBytes, " a mesh file may have"));
    if (const auto nul = detail::nul_byte(text))  // even in a comment: a text file holds none
      throw Error(message(source, ":", nul->line, ": a NUL byte at column ", nul->column, " (not a text file)"));
  }

  // Moves to the next line with data; false at the end of the text.
  bool next() {
    while (pos_ < text_.size()) {
      const std::size_t nl = text_.find('\n', pos_);
      const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      detail::split_fields(line, fields_);
      if (!fields_.empty()) return true;
    }
    return false;
  }

  const std::vector<std::string_view>& fields() const { return fields_; }
  std::size_t line() const { return line_; }
  std::size_t size() const { return text_.size(); }
  const std::string& source() const { return source_; }

  [[noreturn]] void fail(const std::string& what) const { throw Error(message(source_, ":", line_, ": ", what)); }

  std::int64_t integer(std::size_t i, const char* what) const {
    const auto v = detail::integer_field(fields_[i]);
    if (!v) fail(message(what, " \"", shown(fields_[i]), "\" is not an integer"));
    return *v;
  }
  std::int64_t count(std::size_t i, const char* what) const {
    const std::int64_t v = integer(i, what);
    if (v < 0) fail(message(what, " ", v, " is negative"));
    return v;
  }
  double coordinate(std::size_t i) const {
    const auto v = detail::number_field(fields_[i]);
    if (!v) fail(message("coordinate \"", shown(fields_[i]), "\" is not a number"));
    if (!std::isfinite(*v)) fail(message("coordinate \"", shown(fields_[i]), "\" is not a finite number"));
    return *v;
  }

  // The header: the first data line, of 1 to `most` values.
  void header(std::size_t most, const char* layout) {
    if (!next()) throw Error(source_ + ": the file has no header (it is blank or all comments)");
    if (fields_.size() > most) fail(message("the header is ", layout, "; this line has ", fields_.size(), " values"));
  }
  // Refuses `n` items of at least `bytes_each` bytes that the text cannot hold, before room for them is made.
  void check_room(std::int64_t n, std::size_t bytes_each, const char* what) const {
    if (std::uint64_t(n) > text_.size() / bytes_each)
      fail(message(n, " ", what, " cannot fit in the ", text_.size(), " bytes of the file (each takes at least ",
                   bytes_each, ")"));
  }
  // The next item of n, of which i came before.
  void item(std::int64_t i, std::int64_t n, const char* what) {
    if (!next()) fail(message("the file ends after ", i, " of the ", n, " ", what, " its header declares"));
  }
  void expect_end(std::int64_t n, const char* what) {
    if (next()) fail(message("more data after the ", n, " ", what, " the header declares"));
  }

private:
  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
  std::vector<std::string_view> fields_;
};

struct TetgenPoints {
  std::vector<double> xyz;  // 3 coordinates per point, in file order
  std::int64_t first = 0;   // the number of the first point: 0 or 1
  std::int64_t count = 0;
};

// The header: the number of points, their dimension (3), attributes and boundary markers (0 or 1).
std::int64_t read_points_header(TetgenText& in, std::int64_t& attributes, std::int64_t& markers) {
  in.header(4, "<points> [<dimension> [<attributes> [<boundary markers>]]]");
  const auto& h = in.fields();
  const std::int64_t n = in.count(0, "the number of points");
  if (n == 0)
    in.fail("the file lists no points (TetGen then takes them from a .poly or .smesh file, which is not read here)");
  const std::int64_t dim = h.size() > 1 ? in.integer(1, "dimension") : 3;
  if (dim != 3) in.fail(message("dimension ", dim, ": TetGen meshes are 3-dimensional"));
  attributes = h.size() > 2 ? in.count(2, "the number of attributes") : 0;
  markers = h.size() > 3 ? in.integer(3, "the boundary marker flag") : 0;
  if (markers != 0 && markers != 1) in.fail(message("the boundary marker flag ", markers, " is neither 0 nor 1"));
  in.check_room(n, 8, "points");  // "1 0 0 0\n"
  return n;
}

TetgenPoints read_points(std::string_view text, const std::string& source) {
  TetgenText in(text, source);
  std::int64_t attributes = 0, markers = 0;
  TetgenPoints points;
  points.count = read_points_header(in, attributes, markers);
  const std::uint64_t values = 4 + std::uint64_t(attributes) + std::uint64_t(markers);
  points.xyz.reserve(3 * std::size_t(points.count));
  for (std::int64_t i = 0; i < points.count; ++i) {
    in.item(i, points.count, "points");
    if (in.fields().size() != values)
      in.fail(message("a point is its number, 3 coordinates, ", attributes, " attributes and ", markers,
                      " boundary markers: ", values, " values; this line has ", in.fields().size()));
    const std::int64_t number = in.integer(0, "point number");
    if (i == 0 && number != 0 && number != 1)
      in.fail(message("the first point is numbered ", number, "; TetGen numbers points from 0 or from 1"));
    if (i == 0) points.first = number;
    if (number != points.first + i)
      in.fail(message("point ", number, " is out of sequence (expected ", points.first + i, ")"));
    for (std::size_t d = 1; d <= 3; ++d) points.xyz.push_back(in.coordinate(d));
  }
  in.expect_end(points.count, "points");
  return points;
}

struct TetgenTets {
  std::vector<std::array<Index, 4>> tets;  // corners as indices into the points, from 0
  std::vector<std::int64_t> number;        // of each tet, as the file gives it
  std::vector<std::size_t> line;           // where each tet is
};

// The header: the number of tets, 4 nodes each (TetGen's -o2 writes 10), and attributes.
std::int64_t read_tets_header(TetgenText& in, std::int64_t& attributes) {
  in.header(3, "<tetrahedra> [<nodes per tetrahedron> [<attributes>]]");
  const auto& h = in.fields();
  const std::int64_t n = in.count(0, "the number of tetrahedra");
  if (n == 0) in.fail("the file lists no tetrahedra");
  const std::int64_t corners = h.size() > 1 ? in.integer(1, "nodes per tetrahedron") : 4;
  if (corners == 10)
    in.fail(
        "10-node tetrahedra (tetgen -o2) are not supported: their edge nodes would be free particles; "
        "mesh without -o2");
  if (corners != 4) in.fail(message("a tetrahedron has 4 nodes (or 10 with tetgen -o2), not ", corners));
  attributes = h.size() > 2 ? in.count(2, "the number of attributes") : 0;
  in.check_room(n, 10, "tetrahedra");  // "1 1 2 3 4\n"
  return n;
}

TetgenTets read_tets(std::string_view text, const std::string& source, const TetgenPoints& points,
                     const std::string& node_source) {
  TetgenText in(text, source);
  std::int64_t attributes = 0;
  const std::int64_t n = read_tets_header(in, attributes);
  const std::uint64_t values = 5 + std::uint64_t(attributes);
  TetgenTets tets;
  tets.tets.reserve(std::size_t(n));
  tets.number.reserve(std::size_t(n));
  tets.line.reserve(std::size_t(n));
  for (std::int64_t t = 0; t < n; ++t) {
    in.item(t, n, "tetrahedra");
    if (in.fields().size() != values)
      in.fail(message("a tetrahedron is its number, 4 nodes and ", attributes, " attributes: ", values,
                      " values; this line has ", in.fields().size()));
    const std::int64_t number = in.integer(0, "tetrahedron number");
    std::array<Index, 4> tet;
    for (std::size_t k = 0; k < 4; ++k) {
      const std::int64_t node = in.integer(1 + k, "node");
      if (node < points.first || node - points.first >= points.count)
        in.fail(message("tet ", number, " names node ", node, ", which ", node_source, " does not have (its ",
                        points.count, " points are numbered from ", points.first, ")"));
      tet[k] = Index(node - points.first);
    }
    tets.tets.push_back(tet);
    tets.number.push_back(number);
    tets.line.push_back(in.line());
  }
  in.expect_end(n, "tetrahedra");
  return tets;
}

}  // namespace

TetMesh parse_tetgen(std::string_view node_text, const std::string& node_source, std::string_view ele_text,
                     const std::string& ele_source) {
  const TetgenPoints points = read_points(node_text, node_source);
  const TetgenTets tets = read_tets(ele_text, ele_source, points, node_source);
  TetMesh mesh = detail::keep_used_nodes(points.xyz, tets.tets);
  detail::check_read_tet_mesh(mesh, ele_source, [&](std::size_t t) {
    return message("the one numbered ", tets.number[t], " at line ", tets.line[t]);
  });
  return mesh;
}

TetMesh load_tetgen(const std::filesystem::path& file) {
  // x.node, x.ele or x: both files are x.node and x.ele (x may have dots of its own, as tetgen's x.1).
  const std::string ext = file.extension().string();
  const std::filesystem::path stem = ext == ".node" || ext == ".ele" ? file.parent_path() / file.stem() : file;
  const std::filesystem::path node = stem.string() + ".node", ele = stem.string() + ".ele";
  const detail::FileBytes node_bytes = detail::read_file_bytes(node, "TetGen .node file", kMaxTetMeshBytes);
  const detail::FileBytes ele_bytes = detail::read_file_bytes(ele, "TetGen .ele file", kMaxTetMeshBytes);
  return parse_tetgen(node_bytes.view(), node.string(), ele_bytes.view(), ele.string());
}

}  // namespace pbd
