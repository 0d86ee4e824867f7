// Meshes: generators (closed where they should be, counts), topology (edges, bending pairs), the mesh body, and
// OBJ loading with its errors.
#include "pbd/closed_mesh.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/obj_loader.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <utility>

namespace pbd {
namespace {

TEST(MeshGenerators, ClosedSolidsAreClosedAndOutwardOriented) {
  for (const TriangleMesh& m : {dodecahedron_mesh(1.0), icosphere_mesh(0, 1.0), icosphere_mesh(3, 2.0),
                                tube_mesh(12, 5, 0.3, 2.0, true)}) {
    EXPECT_FALSE(closed_mesh_defect(m.triangles, m.num_vertices()).has_value())
        << *closed_mesh_defect(m.triangles, m.num_vertices());
    for (const auto& t : m.triangles) {  // each triangle faces away from the centre (all are convex or star-shaped)
      const Eigen::Vector3d a = m.positions.col(t[0]), b = m.positions.col(t[1]), c = m.positions.col(t[2]);
      EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0.0);
    }
  }
  EXPECT_EQ(dodecahedron_mesh(1.0).num_vertices(), 32u);
  EXPECT_EQ(dodecahedron_mesh(1.0).triangles.size(), 60u);
  EXPECT_EQ(icosphere_mesh(2, 1.0).num_vertices(), 162u);
  EXPECT_EQ(icosphere_mesh(2, 1.0).triangles.size(), 320u);
}

TEST(MeshGenerators, OpenMeshesAreOpen) {
  const TriangleMesh g = grid_mesh(4, 1.0), t = tube_mesh(8, 3, 1.0, 1.0, false);
  EXPECT_NE(closed_mesh_defect(g.triangles, g.num_vertices())->find("open"), std::string::npos);
  EXPECT_NE(closed_mesh_defect(t.triangles, t.num_vertices())->find("open"), std::string::npos);
  EXPECT_THROW(grid_mesh(1, 1.0), Error);
  EXPECT_THROW(icosphere_mesh(9, 1.0), Error);
  EXPECT_THROW(tube_mesh(2, 3, 1.0, 1.0, true), Error);
}

TEST(MeshTopology, EdgesAndBendingPairsOfAGrid) {
  const TriangleMesh g = grid_mesh(3, 1.0);  // 8 triangles
  EXPECT_EQ(mesh_edges(g.triangles).size(), 16u);  // 6 rows + 6 columns + 4 diagonals
  const auto pairs = mesh_bending_pairs(g.triangles);
  EXPECT_EQ(pairs.size(), 8u);  // interior edges: 16 − 8 on the boundary
  for (const auto& p : pairs) {
    EXPECT_NE(p[2], p[3]);
    for (int k = 0; k < 2; ++k) EXPECT_TRUE(p[2 + k] != p[0] && p[2 + k] != p[1]);
  }
  const TriangleMesh s = icosphere_mesh(1, 1.0);
  EXPECT_EQ(mesh_bending_pairs(s.triangles).size(), mesh_edges(s.triangles).size());  // closed: every edge interior
}

// The definition of mesh_edges and mesh_bending_pairs, written the plain way (one map over undirected edges): every
// undirected edge once in first-appearance order as its first triangle names it; a bending pair per edge of exactly
// two triangles, with the corners opposite it in triangle order.
struct ReferenceTopology {
  std::vector<std::array<Index, 2>> edges;
  std::vector<std::array<Index, 4>> pairs;
  explicit ReferenceTopology(const std::vector<std::array<Index, 3>>& tris) {
    std::map<std::pair<Index, Index>, std::size_t> index;
    std::vector<std::vector<Index>> opposite;
    for (const auto& t : tris)
      for (int k = 0; k < 3; ++k) {
        const Index a = t[k], b = t[(k + 1) % 3];
        const auto [it, added] = index.emplace(std::minmax(a, b), edges.size());
        if (added) {
          edges.push_back({a, b});
          opposite.emplace_back();
        }
        opposite[it->second].push_back(t[(k + 2) % 3]);
      }
    for (std::size_t e = 0; e < edges.size(); ++e)
      if (opposite[e].size() == 2) pairs.push_back({edges[e][0], edges[e][1], opposite[e][0], opposite[e][1]});
  }
};

TEST(MeshTopology, EdgesAndBendingPairsComeInTheOrderOfTheirDefinition) {
  std::vector<std::vector<std::array<Index, 3>>> meshes = {
      grid_mesh(7, 1.0).triangles, icosphere_mesh(3, 1.0).triangles, dodecahedron_mesh(1.0).triangles,
      tube_mesh(100, 3, 0.1, 1.0, true).triangles,  // the caps' centres are hubs of 200 half-edges
      load_obj(std::filesystem::path(PBD_TEST_SCENE_DIR) / "meshes" / "pig.obj").triangles};
  // Non-manifold: fins on a tetrahedron's edge, a duplicated triangle, flipped triangles, unused vertex indices.
  meshes.push_back({{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 1, 4}, {1, 0, 5}, {0, 1, 4}, {9, 7, 8}, {7, 9, 8}});
  std::mt19937 rng(3);  // triangle soup on few vertices: many edges shared by 3 or more triangles
  std::vector<std::array<Index, 3>> soup;
  for (int i = 0; i < 3000; ++i) {
    const Index a = rng() % 40, b = (a + 1 + rng() % 39) % 40;
    Index c = rng() % 40;
    while (c == a || c == b) c = rng() % 40;
    soup.push_back({a, b, c});
  }
  meshes.push_back(soup);
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const ReferenceTopology reference(meshes[m]);
    EXPECT_EQ(mesh_edges(meshes[m]), reference.edges) << "mesh " << m;
    EXPECT_EQ(mesh_bending_pairs(meshes[m]), reference.pairs) << "mesh " << m;
  }
  EXPECT_TRUE(mesh_edges({}).empty());
  EXPECT_TRUE(mesh_bending_pairs({}).empty());
}

// closed_mesh_defect's definition written the plain way (a map of directed edges): the first half-edge in triangle
// order whose edge is not used exactly once in each direction, and why.
std::optional<std::string> reference_defect(const std::vector<std::array<Index, 3>>& tris) {
  std::map<std::pair<Index, Index>, Index> directed;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      const Index forward = directed[{a, b}], backward = directed[{b, a}];
      if (forward == 1 && backward == 1) continue;
      const std::string edge = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
      if (forward + backward == 1) return edge + " belongs to one triangle only: the mesh is open";
      if (forward + backward > 2)
        return edge + " is shared by " + std::to_string(forward + backward) + " triangles: the mesh is not manifold";
      return edge + " is used twice in the same direction: the triangles are not consistently oriented";
    }
  return std::nullopt;
}

TEST(ClosedMesh, EveryDefectIsTheFirstInTriangleOrderAsItsDefinitionFindsIt) {
  std::vector<std::vector<std::array<Index, 3>>> meshes = {
      icosphere_mesh(3, 1.0).triangles, dodecahedron_mesh(1.0).triangles, tube_mesh(100, 3, 0.1, 1.0, true).triangles,
      tube_mesh(100, 3, 0.1, 1.0, false).triangles, grid_mesh(5, 1.0).triangles,
      load_obj(std::filesystem::path(PBD_TEST_SCENE_DIR) / "meshes" / "pig.obj").triangles};
  const std::vector<std::array<Index, 3>> tetra = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  meshes.push_back(tetra);
  auto with = [&](std::vector<std::array<Index, 3>> extra) {
    std::vector<std::array<Index, 3>> m = tetra;
    m.insert(m.end(), extra.begin(), extra.end());
    return m;
  };
  meshes.push_back(with({{0, 1, 4}}));             // a fin: shared by 3
  meshes.push_back(with({{0, 2, 1}}));             // a triangle twice: same direction twice
  meshes.push_back({{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 3, 2}});  // one triangle flipped
  std::vector<std::array<Index, 3>> soup;
  std::mt19937 rng(8);
  for (int i = 0; i < 400; ++i) {
    const Index a = rng() % 12, b = (a + 1 + rng() % 11) % 12;
    Index c = rng() % 12;
    while (c == a || c == b) c = rng() % 12;
    soup.push_back({a, b, c});
  }
  meshes.push_back(soup);
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    EXPECT_EQ(closed_mesh_defect(meshes[m], 1'000'000), reference_defect(meshes[m])) << "mesh " << m;
    // The same mesh on particles spread far apart (the sparse path) and shifted (the dense path with an offset).
    for (const auto& [scale, shift] : {std::pair<Index, Index>{997, 3}, std::pair<Index, Index>{1, 5000}}) {
      auto spread = meshes[m];
      for (auto& t : spread)
        for (Index& i : t) i = i * scale + shift;
      EXPECT_EQ(closed_mesh_defect(spread, 100'000'000), reference_defect(spread)) << "mesh " << m << " x" << scale;
    }
  }
}

TEST(MeshBody, GeneratesOnlyTheRequestedSets) {
  World<double> w;
  MeshConstraintSets sets;
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.5));
  sets.area = w.add_constraint_set(Stiffness::pbd_k(1.0));
  MeshBodyOptions o;
  o.origin = {0, 0, 2};
  o.mass = 4.0;
  o.pinned = {0};
  const Body b = add_mesh(w, icosphere_mesh(1, 1.0), o, sets);
  EXPECT_EQ(b.num_particles, 42u);
  EXPECT_TRUE(w.constraints<StretchConstraint<double>>().empty());
  EXPECT_EQ(w.constraints<BendingConstraint<double>>().size(), 120u);
  EXPECT_EQ(w.constraints<AreaConstraint<double>>().size(), 80u);
  EXPECT_TRUE(w.volumes().empty());
  EXPECT_EQ(w.inverse_masses()[0], 0.0);
  EXPECT_DOUBLE_EQ(w.inverse_masses()[1], 42.0 / 4.0);
  EXPECT_NEAR(w.positions().row(2).mean(), 2.0, 1e-9);
  // A volume on an open mesh adds nothing at all.
  MeshConstraintSets vol;
  vol.volume = sets.area;
  const Index before = w.num_particles();
  EXPECT_THROW(add_mesh(w, grid_mesh(3, 1.0), {}, vol), Error);
  EXPECT_EQ(w.num_particles(), before);
}

class ObjFiles : public ::testing::Test {
protected:
  pbd::test::TempDir dir{"pbd_obj_test"};
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path;
  }
  // Expects load_obj(file) to throw naming the file and containing `what`.
  void expect_error(const std::filesystem::path& file, const std::string& what) {
    try {
      load_obj(file);
      ADD_FAILURE() << "accepted " << file;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file.filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  }
};

const char* kTetra = "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

TEST_F(ObjFiles, ClosedTetrahedronLoadsAndTakesAVolume) {
  const TriangleMesh m = load_obj(write("tetra.obj", kTetra));
  EXPECT_EQ(m.num_vertices(), 4u);
  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_FALSE(closed_mesh_defect(m.triangles, 4).has_value());
  World<double> w;
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  add_mesh(w, m, {}, sets);
  EXPECT_NEAR(w.volumes().items[0].rest, 1.0, 1e-12);  // 6 × 1/6
}

TEST_F(ObjFiles, QuadsAreTriangulatedAndNegativeIndicesAreRelative) {
  const TriangleMesh m = load_obj(write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n"));
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (std::array<Index, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<Index, 3>{0, 2, 3}));
}

TEST_F(ObjFiles, OpenAndNonManifoldMeshesNameTheEdgeWhenAVolumeIsAsked) {
  const TriangleMesh open = load_obj(write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"));
  EXPECT_NE(closed_mesh_defect(open.triangles, 4)->find("edge ("), std::string::npos);
  World<double> w;
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  try {
    add_mesh(w, open, {}, sets);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("open"), std::string::npos) << e.what();
  }
  const TriangleMesh fin = load_obj(write("fin.obj", std::string(kTetra) + "v 2 2 2\nf 2 3 5\n"));
  EXPECT_NE(closed_mesh_defect(fin.triangles, 5)->find("manifold"), std::string::npos);
}

TEST_F(ObjFiles, BadFilesNameTheFileAndLine) {
  expect_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "range.obj:4");
  expect_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "out of range");
  expect_error(write("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n"), "out of range");
  expect_error(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "zero.obj:4");
  expect_error(write("short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), "short.obj:3");
  expect_error(write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"), "nan.obj:2");
  expect_error(write("inf.obj", "v 0 0 0\nv 1 1e999 0\nv 0 1 0\nf 1 2 3\n"), "not a finite number");
  expect_error(write("word.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n"), "word.obj:2");
  expect_error(write("twod.obj", "v 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\n"), "3 coordinates");
  expect_error(write("empty.obj", "# nothing\nv 0 0 0\n"), "no faces");
  expect_error("/nonexistent/missing.obj", "cannot read");
}

}  // namespace
}  // namespace pbd
