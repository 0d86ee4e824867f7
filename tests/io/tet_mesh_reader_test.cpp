// Tet mesh readers: one mesh written as Gmsh MSH 2.2, 4.1 and 4.0 (ASCII, and binary in both byte orders) and as
// TetGen .node/.ele (numbered from 0 and from 1) reads back to itself; files tetgen wrote read as the meshes they are;
// malformed files of each format are refused naming the file, the line (or, in binary data, the section and byte)
// and what is wrong; inverted tets are refused naming the tet and where it is; unreadable files are refused by name.
#include "error_checks.hpp"
#include "temp_dir.hpp"
#include "pbd/error.hpp"
#include "pbd/io/tet_mesh_reader.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace pbd {
namespace {

using test::error_of;
using test::expect_words;
using test::replaced;

// --- the mesh ---------------------------------------------------------------------------------------------------

// A bar of 2 × 1 × 1 cells of 6 tets: 12 nodes, 12 tets, 2 · 0.7 · 0.3 m³ (0.7 and 0.3 have no exact binary form, so
// the ASCII files must carry all 17 digits).
TetMesh bar() { return tet_box_mesh({2, 1, 1}, {2.0, 0.7, 0.3}); }
constexpr double kBarVolume = 2.0 * 0.7 * 0.3;

double volume(const TetMesh& m) {
  double v = 0.0;
  for (const auto& t : m.tets)
    v += signed_tet_volume(m.positions.col(t[0]), m.positions.col(t[1]), m.positions.col(t[2]), m.positions.col(t[3]));
  return v;
}

void expect_bar(const TetMesh& got) {
  const TetMesh want = bar();
  ASSERT_EQ(got.num_vertices(), want.num_vertices());
  EXPECT_TRUE(got.positions == want.positions) << "positions differ";  // bit for bit
  EXPECT_EQ(got.tets, want.tets);
  EXPECT_NEAR(volume(got), kBarVolume, 1e-12);
}

std::string num(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

// Line number of the first `needle` in `text` (which must hold it).
int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(std::min(at, text.size())), '\n'));
}
std::string at_line(const std::string& file, const std::string& text, const std::string& needle) {
  return file + ":" + std::to_string(line_of(text, needle)) + ": ";
}

void write(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// --- Gmsh files, written as the MSH format says -------------------------------------------------------------------

// The bar's nodes get sparse tags in descending order, so that the reader must map tags and keep file order; a node
// with tag 5 that no tet names comes first (it must be dropped), on a surface entity with parametric coordinates.
std::uint64_t node_tag(Index v) { return 1000 - 10 * std::uint64_t(v); }
constexpr std::uint64_t kFreeTag = 5;

// Elements of one type, as a version 4 block holds them; version 2 writes them one by one, numbered from 1 on.
struct ElementBlock {
  int dim;
  int type;
  std::vector<std::vector<std::uint64_t>> nodes;
};

// A point, a line, the boundary triangles (Gmsh writes such lower-dimensional elements too), then the tets.
std::vector<ElementBlock> element_blocks(const TetMesh& m) {
  std::vector<ElementBlock> blocks{
      {0, 15, {{node_tag(0)}}}, {1, 1, {{node_tag(0), node_tag(1)}}}, {2, 2, {}}, {3, 4, {}}};
  for (const auto& t : tet_mesh_surface(m)) blocks[2].nodes.push_back({node_tag(t[0]), node_tag(t[1]), node_tag(t[2])});
  for (const auto& t : m.tets)
    blocks[3].nodes.push_back({node_tag(t[0]), node_tag(t[1]), node_tag(t[2]), node_tag(t[3])});
  return blocks;
}

std::size_t count_elements(const std::vector<ElementBlock>& blocks) {
  std::size_t n = 0;
  for (const auto& b : blocks) n += b.nodes.size();
  return n;
}

struct MshFormat {
  std::string version;  // "2.2", "4.1" or "4.0"
  bool binary = false;
  int size_t_bytes = 8;  // data-size of version 4
  bool swap = false;     // binary values in the other byte order
};

// Text, and binary values as the format has them: int 4 bytes, double 8, size_t data-size bytes.
class MshBytes {
public:
  explicit MshBytes(const MshFormat& f) : f_(f) {}
  void text(const std::string& s) { out_ += s; }
  void i32(std::int64_t v) { raw(std::int32_t(v)); }
  void f64(double v) { raw(v); }
  void size(std::uint64_t v) {
    if (f_.size_t_bytes == 4)
      raw(std::uint32_t(v));
    else
      raw(v);
  }
  const std::string& bytes() const { return out_; }

private:
  template <class T>
  void raw(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (f_.swap) std::reverse(b, b + sizeof(T));
    out_.append(b, sizeof(T));
  }
  const MshFormat& f_;
  std::string out_;
};

void entities(MshBytes& o, const MshFormat& f) {
  // A point (with a physical tag), a surface and the volume bounded by it.
  if (!f.binary) {
    o.text("$Entities\n1 0 1 1\n1 0 0 0 1 7 \n1 0 0 0 2 0.7 0.3 0 0 \n1 0 0 0 2 0.7 0.3 1 1 1 1 \n$EndEntities\n");
    return;
  }
  o.text("$Entities\n");
  for (const std::uint64_t n : {1, 0, 1, 1}) o.size(n);
  o.i32(1);
  for (double x : {0.0, 0.0, 0.0}) o.f64(x);
  o.size(1);
  o.i32(7);
  for (int volume = 0; volume < 2; ++volume) {
    o.i32(1);
    for (double x : {0.0, 0.0, 0.0, 2.0, 0.7, 0.3}) o.f64(x);
    o.size(volume);  // physical tags
    if (volume) o.i32(1);
    o.size(volume);  // bounding surfaces
    if (volume) o.i32(1);
  }
  o.text("\n$EndEntities\n");
}

void nodes_v2(MshBytes& o, const TetMesh& m, const MshFormat& f) {
  o.text("$Nodes\n" + std::to_string(m.num_vertices() + 1) + "\n");
  for (Index v = 0; v <= m.num_vertices(); ++v) {
    const std::uint64_t tag = v == 0 ? kFreeTag : node_tag(v - 1);
    const Vec3<double> p = v == 0 ? Vec3<double>(9, 9, 9) : Vec3<double>(m.positions.col(v - 1));
    if (f.binary) {
      o.i32(std::int64_t(tag));
      for (int d = 0; d < 3; ++d) o.f64(p[d]);
    } else {
      o.text(std::to_string(tag) + " " + num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n");
    }
  }
  o.text(f.binary ? "\n$EndNodes\n" : "$EndNodes\n");
}

void elements_v2(MshBytes& o, const std::vector<ElementBlock>& blocks, const MshFormat& f) {
  o.text("$Elements\n" + std::to_string(count_elements(blocks)) + "\n");
  std::int64_t id = 1;
  for (const auto& b : blocks) {
    if (f.binary) {  // one header per block: type, elements, tags each (physical and elementary)
      o.i32(b.type);
      o.i32(std::int64_t(b.nodes.size()));
      o.i32(2);
    }
    for (const auto& e : b.nodes) {
      if (f.binary) {
        for (std::int64_t v : {id++, std::int64_t(b.dim == 3), std::int64_t(1)}) o.i32(v);
        for (const auto n : e) o.i32(std::int64_t(n));
      } else {
        std::string line =
            std::to_string(id++) + " " + std::to_string(b.type) + " 2 " + (b.dim == 3 ? "1" : "0") + " 1";
        for (const auto n : e) line += ' ' + std::to_string(n);
        o.text(line + "\n");
      }
    }
  }
  o.text(f.binary ? "\n$EndElements\n" : "$EndElements\n");
}

void nodes_v4(MshBytes& o, const TetMesh& m, const MshFormat& f) {
  const std::uint64_t nv = m.num_vertices();
  if (f.binary) {
    o.text("$Nodes\n");
    for (const std::uint64_t n : {std::uint64_t(2), nv + 1, kFreeTag, node_tag(0)}) o.size(n);
    o.i32(2);  // the free node, on surface 1 with parametric coordinates u, v
    o.i32(1);
    o.i32(1);
    o.size(1);
    o.size(kFreeTag);
    for (double x : {9.0, 9.0, 9.0, 0.5, 0.25}) o.f64(x);
    o.i32(3);  // the bar's nodes, in volume 1
    o.i32(1);
    o.i32(0);
    o.size(nv);
    for (Index v = 0; v < nv; ++v) o.size(node_tag(v));
    for (Index v = 0; v < nv; ++v)
      for (int d = 0; d < 3; ++d) o.f64(m.positions(d, v));
    o.text("\n$EndNodes\n");
    return;
  }
  const bool v41 = f.version == "4.1";
  auto xyz = [&](Index v) {
    return num(m.positions(0, v)) + " " + num(m.positions(1, v)) + " " + num(m.positions(2, v));
  };
  if (v41) {
    o.text("$Nodes\n2 " + std::to_string(nv + 1) + " 5 1000\n2 1 1 1\n5\n9 9 9 0.5 0.25\n3 1 0 " + std::to_string(nv) +
           "\n");
    for (Index v = 0; v < nv; ++v) o.text(std::to_string(node_tag(v)) + "\n");
    for (Index v = 0; v < nv; ++v) o.text(xyz(v) + "\n");
  } else {  // 4.0: entity tag before dimension, and each node's tag on its coordinates' line
    o.text("$Nodes\n2 " + std::to_string(nv + 1) + "\n1 2 1 1\n5 9 9 9 0.5 0.25\n1 3 0 " + std::to_string(nv) + "\n");
    for (Index v = 0; v < nv; ++v) o.text(std::to_string(node_tag(v)) + " " + xyz(v) + "\n");
  }
  o.text("$EndNodes\n");
}

void elements_v4(MshBytes& o, const std::vector<ElementBlock>& blocks, const MshFormat& f) {
  const std::uint64_t total = count_elements(blocks);
  const std::string n = std::to_string(total);
  if (f.binary) {
    o.text("$Elements\n");
    for (const std::uint64_t v : {std::uint64_t(blocks.size()), total, std::uint64_t(1), total}) o.size(v);
  } else {
    o.text("$Elements\n" + std::to_string(blocks.size()) + " " + n + (f.version == "4.1" ? " 1 " + n : "") + "\n");
  }
  std::uint64_t id = 1;
  for (const auto& b : blocks) {
    if (f.binary) {
      o.i32(b.dim);
      o.i32(1);
      o.i32(b.type);
      o.size(b.nodes.size());
    } else {
      const std::string dim = std::to_string(b.dim);
      o.text((f.version == "4.1" ? dim + " 1 " : "1 " + dim + " ") + std::to_string(b.type) + " " +
             std::to_string(b.nodes.size()) + "\n");
    }
    for (const auto& e : b.nodes) {
      if (f.binary) {
        o.size(id++);
        for (const auto v : e) o.size(v);
      } else {
        std::string line = std::to_string(id++);
        for (const auto v : e) line += ' ' + std::to_string(v);
        o.text(line + " \n");  // Gmsh ends element lines with a space
      }
    }
  }
  o.text(f.binary ? "\n$EndElements\n" : "$EndElements\n");
}

std::string msh(const TetMesh& m, const MshFormat& f, const std::vector<ElementBlock>& blocks) {
  MshBytes o(f);
  o.text("$MeshFormat\n" + f.version + (f.binary ? " 1 " : " 0 ") + std::to_string(f.size_t_bytes) + "\n");
  if (f.binary) {
    o.i32(1);
    o.text("\n");
  }
  o.text("$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"bar\"\n$EndPhysicalNames\n");
  if (f.version[0] == '4') {
    entities(o, f);
    nodes_v4(o, m, f);
    elements_v4(o, blocks, f);
  } else {
    nodes_v2(o, m, f);
    elements_v2(o, blocks, f);
  }
  o.text("$NodeData\nnothing after $Elements is read\n");
  return o.bytes();
}
std::string msh(const TetMesh& m, const MshFormat& f) { return msh(m, f, element_blocks(m)); }

constexpr int kCorruptions = 1000;  // per format

const MshFormat kV22{"2.2"}, kV22Binary{"2.2", true}, kV41{"4.1"}, kV41Binary{"4.1", true}, kV40{"4.0"};

// --- TetGen files -----------------------------------------------------------------------------------------------

struct TetgenFormat {
  Index first = 1;      // the number of the first point
  bool extras = false;  // a point attribute and a boundary marker, a tet attribute
};

// The bar's points, then one no tet names (dropped on reading); comments and a blank line on the way.
std::string tetgen_node(const TetMesh& m, const TetgenFormat& f) {
  std::string s = "# the bar\n" + std::to_string(m.num_vertices() + 1) + (f.extras ? "  3  1  1\n" : "  3  0  0\n");
  for (Index v = 0; v <= m.num_vertices(); ++v) {
    const Vec3<double> p = v < m.num_vertices() ? Vec3<double>(m.positions.col(v)) : Vec3<double>(9, 9, 9);
    s += "  " + std::to_string(v + f.first) + "  " + num(p[0]) + "  " + num(p[1]) + "  " + num(p[2]) +
         (f.extras ? "  0.5  1" : "") + (v == 2 ? "  # a comment after data\n\n" : "\n");
  }
  return s + "# Generated by hand\n";
}

std::string tetgen_ele(const TetMesh& m, const TetgenFormat& f) {
  std::string s = std::to_string(m.tets.size()) + (f.extras ? "  4  1\n" : "  4  0\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    s += "  " + std::to_string(t + f.first);
    for (const Index v : m.tets[t]) s += "  " + std::to_string(v + f.first);
    s += f.extras ? "  7\n" : "\n";
  }
  return s;
}

// --- reading back -----------------------------------------------------------------------------------------------

TEST(TetReadGmsh, EveryVersionAndEncodingReadsBackTheMesh) {
  const test::TempDir dir("pbd_tet_read");
  const std::pair<const char*, MshFormat> formats[] = {{"v22.msh", kV22},
                                                       {"v22_binary.msh", kV22Binary},
                                                       {"v22_binary_swapped.msh", {"2.2", true, 8, true}},
                                                       {"v41.msh", kV41},
                                                       {"v41_binary.msh", kV41Binary},
                                                       {"v41_binary_size4.msh", {"4.1", true, 4}},
                                                       {"v41_binary_swapped.msh", {"4.1", true, 8, true}},
                                                       {"v40.msh", kV40}};
  for (const auto& [name, format] : formats) {
    SCOPED_TRACE(name);
    write(dir / name, msh(bar(), format));
    expect_bar(load_gmsh(dir / name));
    expect_bar(load_tet_mesh(dir / name));
  }
  // Version 2 as Gmsh 2.x wrote it before 2.2 ("2 0 8"): the same layout.
  expect_bar(parse_gmsh(replaced(msh(bar(), kV22), "2.2 0 8", "2 0 8"), "v2.msh"));
  // Windows line ends, and blank lines between sections.
  std::string crlf;
  for (const char c : replaced(msh(bar(), kV41), "$EndNodes\n", "$EndNodes\n\n \n"))
    crlf += c == '\n' ? "\r\n" : std::string(1, c);
  expect_bar(parse_gmsh(crlf, "crlf.msh"));
}

TEST(TetReadTetgen, ZeroAndOneBasedFilesReadBackTheMesh) {
  const test::TempDir dir("pbd_tet_read");
  for (const TetgenFormat format :
       {TetgenFormat{1, false}, TetgenFormat{0, false}, TetgenFormat{1, true}, TetgenFormat{0, true}}) {
    SCOPED_TRACE(testing::Message() << "first " << format.first << ", extras " << format.extras);
    write(dir / "bar.1.node", tetgen_node(bar(), format));
    write(dir / "bar.1.ele", tetgen_ele(bar(), format));
    expect_bar(load_tetgen(dir / "bar.1.node"));
    expect_bar(load_tetgen(dir / "bar.1.ele"));
    expect_bar(load_tetgen(dir / "bar.1"));  // the stem
    expect_bar(load_tet_mesh(dir / "bar.1.ele"));
  }
}

// Files tetgen 1.5.0 wrote for a unit box (tetgen -pqa0.3 box.poly; then -pqAa0.3z for the second pair, whose .poly
// also had a region, so that its tets carry a region attribute, and whose numbering starts at 0).
const char* const kBoxNode = R"(20  3  0  0
   1    0  0  0
   2    1  0  0
   3    1  1  0
   4    0  1  0
   5    0  0  1
   6    1  0  1
   7    1  1  1
   8    0  1  1
   9    0.5  0  0
  10    1  0.5  0
  11    0.5  1  0
  12    0  0.5  0
  13    0.5  0  1
  14    1  0.5  1
  15    0.5  1  1
  16    0  0.5  1
  17    1  0  0.5
  18    0  0  0.5
  19    1  1  0.5
  20    0  1  0.5
# Generated by tetgen -pqa0.3 -Q box.poly
)";
const char* const kBoxEle = R"(22  4  0
    1       8    15    16    20
    2       9    11    15    19
    3      16    12     9    18
    4       9    16    15    20
    5       9    10    14    17
    6      10     9    14    19
    7      11     9    15    20
    8      16     9    15    13
    9      14     9    15    19
   10      12    16     9    20
   11       9    14    13    17
   12      13     5    16    18
   13      14     9    13    15
   14      16     9    13    18
   15       7    14    15    19
   16      11     4    12    20
   17       6    13    14    17
   18       9     2    10    17
   19       1     9    12    18
   20      10     3    11    19
   21       9    10    11    19
   22       9    11    12    20
# Generated by tetgen -pqa0.3 -Q box.poly
)";
const char* const kBoxRegionNode = R"(20  3  0  0
   0    0  0  0
   1    1  0  0
   2    1  1  0
   3    0  1  0
   4    0  0  1
   5    1  0  1
   6    1  1  1
   7    0  1  1
   8    0.5  0  0
   9    1  0.5  0
  10    0.5  1  0
  11    0  0.5  0
  12    0.5  0  1
  13    1  0.5  1
  14    0.5  1  1
  15    0  0.5  1
  16    1  0  0.5
  17    0  0  0.5
  18    1  1  0.5
  19    0  1  0.5
# Generated by tetgen -pqAa0.3zQ boxr.poly
)";
const char* const kBoxRegionEle = R"(22  4  1
    0       7    14    15    19    7
    1       8    10    14    18    7
    2      15    11     8    17    7
    3       8    15    14    19    7
    4       8     9    13    16    7
    5       9     8    13    18    7
    6      10     8    14    19    7
    7      15     8    14    12    7
    8      13     8    14    18    7
    9      11    15     8    19    7
   10       8    13    12    16    7
   11      12     4    15    17    7
   12      13     8    12    14    7
   13      15     8    12    17    7
   14       6    13    14    18    7
   15      10     3    11    19    7
   16       5    12    13    16    7
   17       8     1     9    16    7
   18       0     8    11    17    7
   19       9     2    10    18    7
   20       8     9    10    18    7
   21       8    10    11    19    7
# Generated by tetgen -pqAa0.3zQ boxr.poly
)";

TEST(TetReadTetgen, FilesTetgenWroteReadAsTheirMesh) {
  // TetGen's orientation is this library's: its tets load as written, all positive, filling the box.
  const TetMesh box = parse_tetgen(kBoxNode, "box.1.node", kBoxEle, "box.1.ele");
  EXPECT_EQ(box.num_vertices(), 20u);
  ASSERT_EQ(box.tets.size(), 22u);
  EXPECT_EQ(box.tets[0], (std::array<Index, 4>{7, 14, 15, 19}));
  EXPECT_NEAR(volume(box), 1.0, 1e-12);
  for (const auto& t : box.tets)
    EXPECT_GT(signed_tet_volume(box.positions.col(t[0]), box.positions.col(t[1]), box.positions.col(t[2]),
                                box.positions.col(t[3])),
              0.0);
  const TetMesh region = parse_tetgen(kBoxRegionNode, "boxr.1.node", kBoxRegionEle, "boxr.1.ele");
  EXPECT_TRUE(region.positions == box.positions);
  EXPECT_EQ(region.tets, box.tets);
}

TEST(TetReadFiles, DispatchByExtension) {
  const test::TempDir dir("pbd_tet_read");
  write(dir / "bar.msh", msh(bar(), kV41));
  expect_bar(load_tet_mesh(dir / "bar.msh"));
  write(dir / "bar.node", tetgen_node(bar(), {}));
  write(dir / "bar.ele", tetgen_ele(bar(), {}));
  expect_bar(load_tet_mesh(dir / "bar.node"));
  for (const char* name : {"bar.obj", "bar", "bar.vtu", "bar.MSH"})
    expect_words(error_of([&] { load_tet_mesh(dir / name); }), {name, ".msh (Gmsh)", ".node or .ele (TetGen)"});
}

// --- unreadable files -------------------------------------------------------------------------------------------

TEST(TetReadFiles, UnreadableGmshFilesAreRefusedByName) {
  const test::TempDir dir("pbd_tet_read");
  expect_words(error_of([&] { load_gmsh(dir / "nope.msh"); }), {"nope.msh", "cannot read the Gmsh file"});
  write(dir / "empty.msh", "");
  expect_words(error_of([&] { load_gmsh(dir / "empty.msh"); }), {"empty.msh", "empty (0 bytes)"});
  expect_words(error_of([&] { parse_gmsh("", "none.msh"); }), {"none.msh", "empty (0 bytes)"});
  std::filesystem::create_directories(dir / "folder.msh");
  expect_words(error_of([&] { load_gmsh(dir / "folder.msh"); }), {"folder.msh", "not a regular file"});
  // A FIFO is refused from its type: opening it would block until a writer came.
  ASSERT_EQ(::mkfifo((dir / "fifo.msh").c_str(), 0600), 0);
  expect_words(error_of([&] { load_gmsh(dir / "fifo.msh"); }), {"fifo.msh", "not a regular file"});
  std::ofstream(dir / "huge.msh").close();
  std::filesystem::resize_file(dir / "huge.msh", kMaxTetMeshBytes + 1);  // sparse: costs no disk
  expect_words(error_of([&] { load_gmsh(dir / "huge.msh"); }), {"huge.msh", "536870913 bytes", "more than"});
}

TEST(TetReadFiles, UnreadableTetgenFilesAreRefusedByName) {
  const test::TempDir dir("pbd_tet_read");
  expect_words(error_of([&] { load_tetgen(dir / "nope"); }), {"nope.node", "cannot read the TetGen .node file"});
  write(dir / "half.node", tetgen_node(bar(), {}));
  expect_words(error_of([&] { load_tetgen(dir / "half.node"); }), {"half.ele", "cannot read the TetGen .ele file"});
  write(dir / "empty.node", tetgen_node(bar(), {}));
  write(dir / "empty.ele", "");
  expect_words(error_of([&] { load_tetgen(dir / "empty.node"); }), {"empty.ele", "empty (0 bytes)"});
  expect_words(error_of([&] { parse_tetgen("", "none.node", "1 4", "none.ele"); }), {"none.node", "empty (0 bytes)"});
  std::filesystem::create_directories(dir / "folder.node");
  expect_words(error_of([&] { load_tetgen(dir / "folder"); }), {"folder.node", "not a regular file"});
  ASSERT_EQ(::mkfifo((dir / "fifo.node").c_str(), 0600), 0);
  expect_words(error_of([&] { load_tetgen(dir / "fifo"); }), {"fifo.node", "not a regular file"});
  write(dir / "huge.node", tetgen_node(bar(), {}));
  std::ofstream(dir / "huge.ele").close();
  std::filesystem::resize_file(dir / "huge.ele", kMaxTetMeshBytes + 1);
  expect_words(error_of([&] { load_tetgen(dir / "huge.ele"); }), {"huge.ele", "536870913 bytes", "more than"});
}

// --- malformed files --------------------------------------------------------------------------------------------

struct BadCase {
  std::string text;
  std::vector<std::string> words;
};

void expect_gmsh_errors(const std::vector<BadCase>& cases) {
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "case " << i);
    const std::string message = error_of([&] { parse_gmsh(cases[i].text, "bad.msh"); });
    for (const auto& w : cases[i].words)
      EXPECT_NE(message.find(w), std::string::npos) << "no \"" << w << "\" in: " << message;
    EXPECT_EQ(message.rfind("bad.msh", 0), 0u) << message;
    EXPECT_LT(message.size(), 400u) << message;
  }
}

TEST(TetReadGmsh, MalformedAsciiIsRefusedNamingTheLine) {
  const std::string v22 = msh(bar(), kV22);
  const std::string node1 = "990 1 0 0\n";    // node 1 of the bar
  const std::string tet0 = " 4 2 1 1 1000 ";  // the first tet, which starts at node 0
  const int first_tet = 3 + 20;               // its element number: after the point, the line and 20 triangles
  auto edit = [&](const std::string& from, const std::string& to) { return replaced(v22, from, to); };
  auto line = [&](const std::string& text, const std::string& needle) { return at_line("bad.msh", text, needle); };
  const std::string duplicate = edit(node1, "1000 1 0 0\n"), unknown = edit(tet0, " 4 2 1 1 77 ");
  const std::string no_tets =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n1 15 2 0 1 1\n$EndElements\n";
  expect_gmsh_errors({
      {edit("$MeshFormat\n", "$MeshFormatt\n"), {"bad.msh:1: ", "the first line is not $MeshFormat"}},
      {edit("2.2 0 8", "3.0 0 8"), {"bad.msh:2: ", "MSH version 3.0 is not supported; versions 2.2 and 4.1 are"}},
      {edit("2.2 0 8", "2.2 0"), {"bad.msh:2: ", "version, file-type and data-size"}},
      {edit("2.2 0 8", "2.2 2 8"), {"bad.msh:2: ", "file-type 2 is neither 0 (ASCII) nor 1 (binary)"}},
      {edit("2.2 0 8", "2.2 0 4"), {"bad.msh:2: ", "data-size 4"}},
      {edit("$EndMeshFormat\n", ""), {"bad.msh:3: ", "expected $EndMeshFormat"}},
      {edit("$EndPhysicalNames\n", ""), {"bad.msh:4: ", "$PhysicalNames has no $EndPhysicalNames line"}},
      {edit("$EndPhysicalNames\n", "$EndPhysicalNames\njunk\n"), {"bad.msh:8: ", "expected a section", "\"junk\""}},
      {duplicate, {line(duplicate, "1000 1 0 0"), "node tag 1000 appears twice (first at line 11)"}},
      {edit(node1, "0 1 0 0\n"), {line(v22, node1), "node tag 0 is not positive"}},
      {edit(node1, "x1 1 0 0\n"), {line(v22, node1), "node tag \"x1\" is not an integer"}},
      {edit(node1, "990 1 zero 0\n"), {line(v22, node1), "coordinate \"zero\" is not a number"}},
      {edit(node1, "990 1 nan 0\n"), {line(v22, node1), "coordinate \"nan\" is not a finite number"}},
      {edit(node1, "990 1 -1e999 0\n"), {line(v22, node1), "coordinate \"-1e999\" is not a finite number"}},
      {edit(node1, "990 1 0\n"), {line(v22, node1), "a node is a tag and 3 coordinates; this line has 3 values"}},
      {edit("$Nodes\n13\n", "$Nodes\n14\n"), {line(v22, "$EndNodes"), "$Nodes declares 14 nodes but has 13"}},
      {edit("$Nodes\n13\n", "$Nodes\n12\n"), {"bad.msh:22: ", "expected $EndNodes after the 12 nodes"}},
      {edit("$Nodes\n13\n", "$Nodes\n99999999999\n"), {"bad.msh:9: ", "99999999999 nodes cannot fit in the"}},
      {edit("$Nodes\n13\n", "$Nodes\n-1\n"), {"bad.msh:9: ", "the number of nodes -1 is negative"}},
      {edit("$Nodes\n13\n", "$Nodes\n13 0\n"), {"bad.msh:9: ", "the number of nodes alone on its line"}},
      {edit("$EndNodes\n", ""), {"expected $EndNodes after the 13 nodes the section declares, found \"$Elements\""}},
      {v22.substr(0, v22.find("$EndNodes")), {"the file ends inside $Nodes"}},
      {v22.substr(0, v22.find("$Elements")), {"the file has no $Elements section"}},
      {replaced(edit("$Nodes\n", "$Comments\n"), "$EndNodes\n", "$EndComments\n"),
       {"bad.msh:24: ", "$Elements comes before $Nodes"}},
      {unknown,
       {line(unknown, " 77 "), "element " + std::to_string(first_tet) + " names node 77, which $Nodes does not have"}},
      {edit(tet0, " 4 2 1 1 "), {line(v22, tet0), "a 4-node tetrahedron with 2 tags is 9 values; this line has 8"}},
      {edit(" 15 2 0 1 1000", " 99 2 0 1 1000"), {"bad.msh:26: ", "element type 99 is not one this reader knows"}},
      {edit(" 15 2 0 1 1000", " 11 2 0 1 1000"),
       {"bad.msh:26: ", "element type 11 (10-node tetrahedron) is a volume element, and only 4-node tetrahedra"}},
      {edit(" 15 2 0 1 1000", " 5 2 0 1 1000"), {"bad.msh:26: ", "8-node hexahedron"}},
      {edit(" 15 2 0 1 1000", " 15 99 0 1 1000"), {"bad.msh:26: ", "a 1-node point with 99 tags is 103 values"}},
      {edit(" 15 2 0 1 1000", " 15 -2 0 1 1000"), {"bad.msh:26: ", "number-of-tags -2 is negative"}},
      {edit("$Elements\n34\n", "$Elements\n35\n"),
       {line(v22, "$EndElements"), "$Elements declares 35 elements but has 34"}},
      {edit("$EndElements\n", "$EndElement\n"), {"expected $EndElements after the 34 elements"}},
      {no_tets, {"bad.msh: the file has no 4-node tetrahedra (element type 4)"}},
  });
  // The first tet naming node 1000 twice: check_tet_mesh refuses it, and the message says where it is.
  const std::string twice = edit(tet0 + "990 ", tet0 + "1000 ");
  expect_gmsh_errors(
      {{twice,
        {"bad.msh: tet 0 names vertex 0 twice",
         "it is element " + std::to_string(first_tet) + " at line " + std::to_string(line_of(twice, tet0))}}});
}

TEST(TetReadGmsh, MalformedVersion4AsciiIsRefusedNamingTheLine) {
  const std::string v41 = msh(bar(), kV41), v40 = msh(bar(), kV40);
  auto line = [&](const std::string& text, const std::string& needle) { return at_line("bad.msh", text, needle); };
  const std::string nodes = "$Nodes\n2 13 5 1000\n", bar_block = "3 1 0 12\n", free_block = "2 1 1 1\n";
  expect_gmsh_errors({
      {replaced(v41, nodes, "$Nodes\n2 13 5\n"),
       {line(v41, "2 13 5 1000"), "the $Nodes header is 4 values; this line has 3"}},
      {replaced(v41, nodes, "$Nodes\n2 14 5 1000\n"),
       {line(v41, "2 13 5 1000"), "the header declares 14 nodes; its blocks hold 13"}},
      {replaced(v41, nodes, "$Nodes\n2 12 5 1000\n"), {line(v41, bar_block), "the blocks hold more than the 12 nodes"}},
      {replaced(v41, nodes, "$Nodes\n3 13 5 1000\n"),
       {line(v41, "$EndNodes"), "$Nodes declares 3 node blocks but has 2"}},
      {replaced(v41, nodes, "$Nodes\n2 13 5 -1000\n"), {line(v41, "2 13 5 1000"), "maxNodeTag -1000 is negative"}},
      {replaced(v41, nodes, "$Nodes\n2 9999999999 5 1000\n"),
       {line(v41, "2 13 5 1000"), "9999999999 nodes cannot fit"}},
      {replaced(v41, bar_block, "7 1 0 12\n"), {line(v41, bar_block), "entity dimension 7 is not 0, 1, 2 or 3"}},
      {replaced(v41, free_block, "2 1 2 1\n"), {line(v41, free_block), "parametric flag 2 is not 0 or 1"}},
      {replaced(v41, bar_block, "3 1 0\n"), {line(v41, bar_block), "a node block header is 4 values; this line has 3"}},
      {replaced(v41, "9 9 9 0.5 0.25\n", "9 9 9 0.5\n"),
       {line(v41, "9 9 9 0.5"), "a node's coordinates are 5 values in this block; this line has 4"}},
      {replaced(v41, "\n990\n", "\n990 0\n"),
       {"bad.msh:" + std::to_string(line_of(v41, "\n990\n") + 1) + ": ",
        "a node tag is alone on its line; this line has 2"}},
      {replaced(v41, "3 1 4 12\n", "3 1 29 12\n"), {line(v41, "3 1 4 12"), "20-node tetrahedron) is a volume element"}},
      {replaced(v41, "3 1 4 12\n", "3 1 4 13\n"), {line(v41, "3 1 4 12"), "the blocks hold more than the 34 elements"}},
      {replaced(v41, "2 1 2 20\n3 ", "2 1 2 20\n3 7 "),
       {"bad.msh:" + std::to_string(line_of(v41, "2 1 2 20") + 1) + ": ",
        "a 3-node triangle is a tag and 3 node tags; this line has 5"}},
      {replaced(v41, "\n4 34 1 34\n", "\n4 33 1 34\n"),
       {line(v41, "3 1 4 12"), "the blocks hold more than the 33 elements"}},
      {replaced(v41, "\n4 34 1 34\n", "\n5 34 1 34\n"),
       {line(v41, "$EndElements"), "$Elements declares 5 element blocks but has 4"}},
      {replaced(v41, "\n4 34 1 34\n", "\n4 34 1\n"), {"the $Elements header is 4 values; this line has 3"}},
      {replaced(v40, "\n2 13\n", "\n2 13 5 1000\n"), {"the $Nodes header is 2 values; this line has 4"}},
      {replaced(v40, "5 9 9 9 0.5 0.25\n", "5 9 9 9\n"),
       {line(v40, "5 9 9 9"), "a node is a tag and 5 coordinates in this block; this line has 4"}},
      {replaced(v41, "$EndEntities\n", ""), {line(v41, "$Entities"), "$Entities has no $EndEntities line"}},
  });
}

// The byte offset of `needle` in `bytes` (which must hold it).
std::size_t offset_of(const std::string& bytes, const std::string& needle) {
  const auto at = bytes.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return at;
}

// `bytes` with `value` written over them at `at`, in this machine's byte order.
template <class T>
std::string with_value(std::string bytes, std::size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
  return bytes;
}

TEST(TetReadGmsh, MalformedBinaryIsRefusedNamingTheSectionAndByte) {
  const std::string v41 = msh(bar(), kV41Binary), v22 = msh(bar(), kV22Binary);
  const std::size_t one41 = offset_of(v41, "4.1 1 8\n") + 8, one22 = offset_of(v22, "2.2 1 8\n") + 8;
  const std::size_t nodes41 = offset_of(v41, "$Nodes\n") + 7;  // numEntityBlocks, numNodes, min, max, then blocks
  const std::size_t elements41 = offset_of(v41, "$Elements\n") + 10;
  const std::size_t nodes22 = offset_of(v22, "$Nodes\n13\n") + 10;  // the free node's tag, then its coordinates
  const std::string byte = "bad.msh: byte ";
  auto at = [&](std::size_t offset, const char* section) { return byte + std::to_string(offset) + " in " + section; };
  std::vector<ElementBlock> bad_type = element_blocks(bar());
  bad_type[0].type = 99;
  TetMesh nan_mesh = bar();
  nan_mesh.positions(1, 1) = std::nan("");
  expect_gmsh_errors({
      {with_value(v41, one41, std::int32_t(2)), {at(one41, "$MeshFormat"), "the endianness check reads 2, not 1"}},
      {replaced(v41, "4.1 1 8", "4.1 1 2"), {"bad.msh:2: ", "data-size 2 is not a size of size_t"}},
      {replaced(v41, "4.1 1 8", "4.0 1 8"), {"bad.msh:2: ", "binary MSH 4.0 is not supported"}},
      {replaced(v22, "2.2 1 8", "2.2 1 4"), {"bad.msh:2: ", "MSH 2 files hold 8-byte doubles"}},
      {with_value(v41, nodes41 + 8, std::uint64_t(1) << 40), {at(nodes41, "$Nodes"), "1099511627776 nodes cannot fit"}},
      {with_value(v41, nodes41, std::uint64_t(1) << 40), {at(nodes41, "$Nodes"), "node blocks cannot fit"}},
      {with_value(v41, nodes41 + 32 + 12, std::uint64_t(14)),
       {at(nodes41 + 32, "$Nodes"), "the blocks hold more than the 13 nodes"}},
      {with_value(v41, nodes41 + 32 + 8, std::int32_t(3)), {at(nodes41 + 32, "$Nodes"), "parametric flag 3"}},
      {with_value(v41, nodes41 + 32 + 20, std::uint64_t(0)),
       {at(nodes41 + 32 + 20, "$Nodes"), "node tag 0 is not a tag"}},
      {with_value(v41, nodes41 + 8, std::uint64_t(14)),
       {at(nodes41, "$Nodes"), "the header declares 14 nodes; its blocks hold 13"}},
      {with_value(v41, elements41 + 8, std::uint64_t(33)),
       {"in $Elements", "the blocks hold more than the 33 elements"}},
      {msh(bar(), kV41Binary, bad_type),
       {at(elements41 + 32, "$Elements"), "element type 99 is not one this reader knows"}},
      {msh(nan_mesh, kV41Binary), {"in $Nodes", "node 990 has a non-finite coordinate (1, nan, 0)"}},
      {with_value(v22, one22, std::int32_t(0x02000000)), {at(one22, "$MeshFormat"), "endianness check reads 33554432"}},
      {with_value(v22, nodes22, std::int32_t(0)), {at(nodes22, "$Nodes"), "node tag 0 is not positive"}},
      {replaced(v22, "$Nodes\n13\n", "$Nodes\n99999999\n"), {"99999999 nodes cannot fit"}},
      {replaced(v22, "$Elements\n34\n", "$Elements\n33\n"),
       {"in $Elements", "an element header announces 12 elements; 11 of the 33"}},
      {msh(bar(), kV22Binary, bad_type), {"in $Elements", "element type 99 is not one this reader knows"}},
      {msh(nan_mesh, kV22Binary), {"in $Nodes", "node 990 has a non-finite coordinate"}},
  });
  // Cut anywhere before its last byte, a binary file is refused (never read out of bounds): past the first binary
  // data, by byte offset.
  for (const std::string& whole : {v41, v22, msh(bar(), {"4.1", true, 4, true})}) {
    const std::size_t end = whole.find("$EndElements") + std::strlen("$EndElements");
    for (std::size_t n = 1; n < end; ++n) {
      const std::string message = error_of([&] { parse_gmsh(whole.substr(0, n), "cut.msh"); });
      ASSERT_EQ(message.rfind("cut.msh", 0), 0u) << "cut at " << n << ": " << message;
      if (n > whole.find("$Nodes") + 7) {
        EXPECT_NE(message.find(": byte "), std::string::npos) << n << ": " << message;
      }
    }
  }
}

// Bytes flipped at random (a fixed seed): every file is read or refused with a pbd::Error naming it, never a crash,
// another exception or a huge allocation.
TEST(TetReadGmsh, CorruptedFilesAreReadOrRefusedByName) {
  std::mt19937 random(7);
  for (const MshFormat& format : {kV22, kV22Binary, kV41, kV41Binary, kV40, MshFormat{"4.1", true, 4, true}}) {
    const std::string whole = msh(bar(), format);
    for (int i = 0; i < kCorruptions; ++i) {
      std::string bytes = whole;
      for (int k = 0, n = 1 + int(random() % 4); k < n; ++k)
        bytes[random() % bytes.size()] = char(random() % 4 ? random() % 256 : "0123456789 \n$-.e"[random() % 17]);
      try {
        parse_gmsh(bytes, "corrupt.msh");
      } catch (const Error& e) {
        ASSERT_EQ(std::string(e.what()).rfind("corrupt.msh", 0), 0u) << e.what();
      }
    }
  }
}

TEST(TetReadTetgen, MalformedFilesAreRefusedNamingTheLine) {
  const TetgenFormat format{1, true};
  const std::string node = tetgen_node(bar(), format), ele = tetgen_ele(bar(), format);
  struct Case {
    std::string node, ele;
    std::vector<std::string> words;
  };
  auto in_node = [&](const std::string& from, const std::string& to) { return replaced(node, from, to); };
  auto in_ele = [&](const std::string& from, const std::string& to) { return replaced(ele, from, to); };
  const std::string point2 = "  2  1  0  0  0.5  1", tet1 = "  1  1  2  5  11  7";
  const std::vector<Case> cases = {
      {in_node("13  3  1  1", "13  2  1  1"), ele, {"bar.node:2: ", "dimension 2: TetGen meshes are 3-dimensional"}},
      {in_node("13  3  1  1", "13  3  1  2"), ele, {"bar.node:2: ", "the boundary marker flag 2 is neither 0 nor 1"}},
      {in_node("13  3  1  1", "13  3  1  1  1"), ele, {"bar.node:2: ", "the header is <points> [<dimension>"}},
      {in_node("13  3  1  1", "13  3  -1  1"), ele, {"bar.node:2: ", "the number of attributes -1 is negative"}},
      {in_node("13  3  1  1", "0  3  1  1"), ele, {"bar.node:2: ", "the file lists no points"}},
      {in_node("13  3  1  1", "14  3  1  1"),
       ele,
       {"bar.node:17: ", "the file ends after 13 of the 14 points its header declares"}},
      {in_node("13  3  1  1", "12  3  1  1"),
       ele,
       {"bar.node:16: ", "more data after the 12 points the header declares"}},
      {in_node("13  3  1  1", "999999999  3  1  1"), ele, {"bar.node:2: ", "999999999 points cannot fit"}},
      {in_node("  1  0  0  0", "  2  0  0  0"),
       ele,
       {"bar.node:3: ", "the first point is numbered 2; TetGen numbers points from 0 or from 1"}},
      {in_node(point2, "  3  1  0  0  0.5  1"), ele, {"bar.node:4: ", "point 3 is out of sequence (expected 2)"}},
      {in_node(point2, "  2  1  0  0  0.5"), ele, {"bar.node:4: ", "6 values; this line has 5"}},
      {in_node(point2, "  2  1  O  0  0.5  1"), ele, {"bar.node:4: ", "coordinate \"O\" is not a number"}},
      {in_node(point2, "  2  1  inf  0  0.5  1"), ele, {"bar.node:4: ", "coordinate \"inf\" is not a finite number"}},
      {in_node(point2, "  2.0  1  0  0  0.5  1"), ele, {"bar.node:4: ", "point number \"2.0\" is not an integer"}},
      {"# nothing but a comment\n\n", ele, {"bar.node: the file has no header"}},
      {node, in_ele("12  4  1", "12  10  1"), {"bar.ele:1: ", "10-node tetrahedra (tetgen -o2) are not supported"}},
      {node,
       in_ele("12  4  1", "12  3  1"),
       {"bar.ele:1: ", "a tetrahedron has 4 nodes (or 10 with tetgen -o2), not 3"}},
      {node, in_ele("12  4  1", "0  4  1"), {"bar.ele:1: ", "the file lists no tetrahedra"}},
      {node, in_ele("12  4  1", "13  4  1"), {"bar.ele:13: ", "the file ends after 12 of the 13 tetrahedra"}},
      {node, in_ele("12  4  1", "11  4  1"), {"bar.ele:13: ", "more data after the 11 tetrahedra"}},
      {node, in_ele("12  4  1", "99999999  4  1"), {"bar.ele:1: ", "99999999 tetrahedra cannot fit"}},
      {node,
       in_ele(tet1, "  1  99  2  5  11  7"),
       {"bar.ele:2: ", "tet 1 names node 99, which bar.node does not have (its 13 points are numbered from 1)"}},
      {node, in_ele(tet1, "  1  0  2  5  11  7"), {"bar.ele:2: ", "tet 1 names node 0, which bar.node does not have"}},
      {node,
       in_ele(tet1, "  1  1  2  5  11"),
       {"bar.ele:2: ", "a tetrahedron is its number, 4 nodes and 1 attributes: 6 values; this line has 5"}},
      {node, in_ele(tet1, "  1  1  2.5  5  11  7"), {"bar.ele:2: ", "node \"2.5\" is not an integer"}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "case " << i);
    const std::string message = error_of([&] { parse_tetgen(cases[i].node, "bar.node", cases[i].ele, "bar.ele"); });
    for (const auto& w : cases[i].words)
      EXPECT_NE(message.find(w), std::string::npos) << "no \"" << w << "\" in: " << message;
    EXPECT_LT(message.size(), 400u) << message;
  }
}

TEST(TetReadTetgen, CorruptedFilesAreReadOrRefusedByName) {
  std::mt19937 random(7);
  const TetgenFormat format{0, true};
  const std::string node = tetgen_node(bar(), format), ele = tetgen_ele(bar(), format);
  for (int i = 0; i < kCorruptions; ++i) {
    std::string texts[2] = {node, ele};
    std::string& text = texts[random() % 2];
    for (int k = 0, n = 1 + int(random() % 4); k < n; ++k)
      text[random() % text.size()] = char(random() % 4 ? random() % 256 : "0123456789 \n#-.e"[random() % 17]);
    try {
      parse_tetgen(texts[0], "corrupt.node", texts[1], "corrupt.ele");
    } catch (const Error& e) {
      const std::string message = e.what();
      ASSERT_TRUE(message.rfind("corrupt.node", 0) == 0 || message.rfind("corrupt.ele", 0) == 0) << message;
    }
  }
}

// --- inverted tets ----------------------------------------------------------------------------------------------

TEST(TetReadInverted, AnInvertedTetIsRefusedNamingItAndWhereItIs) {
  TetMesh inverted = bar();
  std::swap(inverted.tets[3][1], inverted.tets[3][2]);
  const int element = 3 + 20 + 3;  // after the point, the line and 20 triangles, the 4th tet
  const std::string v22 = msh(inverted, kV22);
  const std::string tet3 = std::to_string(element) + " 4 2 1 1 ";
  expect_words(error_of([&] { parse_gmsh(v22, "bar.msh"); }),
               {"bar.msh: tet 3 is inverted (signed volume -",
                "it is element " + std::to_string(element) + " at line " + std::to_string(line_of(v22, tet3))});
  expect_words(error_of([&] { parse_gmsh(msh(inverted, kV41Binary), "bar.msh"); }),
               {"bar.msh: tet 3 is inverted", "it is element " + std::to_string(element) + " at byte "});
  const TetgenFormat format{1, false};
  const std::string ele = tetgen_ele(inverted, format);
  expect_words(error_of([&] { parse_tetgen(tetgen_node(inverted, format), "bar.node", ele, "bar.ele"); }),
               {"bar.ele: tet 3 is inverted", "it is the one numbered 4 at line 5"});
  // A degenerate tet: node 10, the top corner of tet 0 (nodes 0, 1, 4, 10), moved down onto the plane of the others.
  TetMesh flat = bar();
  flat.positions(2, 10) = 0.0;
  const std::string v41 = msh(flat, kV41);
  expect_words(error_of([&] { parse_gmsh(v41, "flat.msh"); }),
               {"flat.msh: tet 0 is degenerate (volume 0 m^3",
                "it is element 23 at line " + std::to_string(line_of(v41, "\n23 ") + 1)});
}

}  // namespace
}  // namespace pbd
