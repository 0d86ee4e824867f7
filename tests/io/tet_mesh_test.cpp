// Tet meshes: the generated box (volume, orientation, conformity), its boundary surface, and the checks that refuse
// inverted, degenerate and malformed tets by index.
#include "pbd/closed_mesh.hpp"
#include "pbd/error.hpp"
#include "pbd/io/tet_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace pbd {
namespace {

double mesh_volume(const TetMesh& m) {
  double v = 0.0;
  for (const auto& t : m.tets)
    v += signed_tet_volume(m.positions.col(t[0]), m.positions.col(t[1]), m.positions.col(t[2]), m.positions.col(t[3]));
  return v;
}

// 6V of a closed surface, by the divergence theorem (as constraints/volume.hpp measures it).
double surface_volume(const TetMesh& m, const std::vector<std::array<Index, 3>>& tris) {
  double v6 = 0.0;
  for (const auto& t : tris)
    v6 += Vec3<double>(m.positions.col(t[0])).cross(Vec3<double>(m.positions.col(t[1])))
              .dot(Vec3<double>(m.positions.col(t[2])));
  return v6 / 6.0;
}

std::string error_of(const TetMesh& m) {
  try {
    check_tet_mesh(m, "bar.msh");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(TetBox, FillsTheBoxWithPositiveConformingTets) {
  for (const auto& [cells, size] : {std::pair{std::array{1, 1, 1}, std::array{1.0, 1.0, 1.0}},
                                    std::pair{std::array{5, 2, 3}, std::array{2.0, 0.4, 0.3}},
                                    std::pair{std::array{10, 1, 1}, std::array{1.0, 0.1, 0.1}}}) {
    const TetMesh m = tet_box_mesh(cells, size);
    EXPECT_EQ(m.num_vertices(), (cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1));
    ASSERT_EQ(m.tets.size(), std::size_t(6 * cells[0] * cells[1] * cells[2]));
    EXPECT_EQ(error_of(m), "");  // every tet positive, none degenerate
    EXPECT_NEAR(mesh_volume(m), size[0] * size[1] * size[2], 1e-12);
    // Conforming: the boundary is exactly the box's 2·(xy + yz + zx) cell faces, two triangles each, and closed.
    const auto surface = tet_mesh_surface(m);
    EXPECT_EQ(surface.size(), std::size_t(4 * (cells[0] * cells[1] + cells[1] * cells[2] + cells[2] * cells[0])));
    EXPECT_FALSE(closed_mesh_defect(surface, m.num_vertices()).has_value());
    EXPECT_NEAR(surface_volume(m, surface), size[0] * size[1] * size[2], 1e-12);
  }
}

// Spatial order: the same tets (each the same four points in the same order, so the same orientation), the vertices
// renumbered so that the first half lies below the second along the box's longest side at every level of the
// bisection down to 32 vertices, the tets sorted by their smallest vertex; the same result every time.
TEST(TetMeshOrder, RenumbersByRecursiveBisectionKeepingEveryTet) {
  TetMesh m = tet_box_mesh({9, 3, 4}, {0.9, 0.3, 0.4});
  // Scramble the numbering first (a fixed permutation), as a mesher leaves it.
  const Index n = m.num_vertices();
  std::vector<Index> scramble(n);
  for (Index v = 0; v < n; ++v) scramble[v] = Index((std::uint64_t(v) * 97) % n);  // 97 is prime to 400
  TetMesh shuffled;
  shuffled.positions.resize(3, n);
  for (Index v = 0; v < n; ++v) shuffled.positions.col(scramble[v]) = m.positions.col(v);
  shuffled.tets = m.tets;
  for (auto& t : shuffled.tets)
    for (Index& v : t) v = scramble[v];
  std::vector<Index> new_index;
  const TetMesh o = spatially_ordered(shuffled, &new_index);
  ASSERT_EQ(o.num_vertices(), n);
  ASSERT_EQ(o.tets.size(), shuffled.tets.size());
  EXPECT_EQ(error_of(o), "");
  EXPECT_NEAR(mesh_volume(o), 0.9 * 0.3 * 0.4, 1e-12);
  std::vector<Index> seen(n, 0);
  for (Index v = 0; v < n; ++v) {
    ASSERT_LT(new_index[v], n);
    ++seen[new_index[v]];
    EXPECT_EQ(Vec3<double>(o.positions.col(new_index[v])), Vec3<double>(shuffled.positions.col(v))) << v;
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](Index c) { return c == 1; }));
  // Every tet is there, its corners in order.
  std::vector<std::array<Index, 4>> mapped = shuffled.tets, got = o.tets;
  for (auto& t : mapped)
    for (Index& v : t) v = new_index[v];
  std::sort(mapped.begin(), mapped.end());
  std::sort(got.begin(), got.end());
  EXPECT_EQ(mapped, got);
  for (std::size_t k = 1; k < o.tets.size(); ++k)
    EXPECT_LE(*std::min_element(o.tets[k - 1].begin(), o.tets[k - 1].end()),
              *std::min_element(o.tets[k].begin(), o.tets[k].end()));
  // The first split: along x (0.9 m is the longest side), the lower 200 vertices first.
  double first_max = -1, second_min = 2;
  for (Index v = 0; v < n; ++v)
    (v < n / 2 ? first_max : second_min) =
        v < n / 2 ? std::max(first_max, o.positions(0, v)) : std::min(second_min, o.positions(0, v));
  EXPECT_LE(first_max, second_min);
  const TetMesh again = spatially_ordered(shuffled);
  EXPECT_EQ(again.tets, o.tets);
  EXPECT_EQ(again.positions, o.positions);
  TetMesh bad = shuffled;
  bad.tets[5][2] = n;  // out of range
  EXPECT_THROW(spatially_ordered(bad), Error);
}

TEST(TetBox, RefusesBadCellsAndSizes) {
  EXPECT_THROW(tet_box_mesh({0, 1, 1}, {1, 1, 1}), Error);
  EXPECT_THROW(tet_box_mesh({1, 1, 1}, {1, -1, 1}), Error);
  EXPECT_THROW(tet_box_mesh({1, 1, 1}, {1, 1, std::nan("")}), Error);
  EXPECT_THROW(tet_box_mesh({100000, 100000, 100000}, {1, 1, 1}), Error);
}

TEST(TetMeshCheck, NamesTheInvertedDegenerateOrMalformedTet) {
  TetMesh m = tet_box_mesh({2, 1, 1}, {2.0, 1.0, 1.0});
  TetMesh inverted = m;
  std::swap(inverted.tets[7][1], inverted.tets[7][2]);
  EXPECT_NE(error_of(inverted).find("bar.msh: tet 7 is inverted"), std::string::npos) << error_of(inverted);
  TetMesh flat = m;
  flat.positions.col(flat.tets[3][3]) = flat.positions.col(flat.tets[3][0]) +
      0.5 * (flat.positions.col(flat.tets[3][1]) - flat.positions.col(flat.tets[3][0]));
  EXPECT_NE(error_of(flat).find("degenerate"), std::string::npos) << error_of(flat);
  TetMesh out_of_range = m;
  out_of_range.tets[4][2] = 99;
  EXPECT_NE(error_of(out_of_range).find("tet 4 names vertex 99; the mesh has 12"), std::string::npos);
  TetMesh twice = m;
  twice.tets[2][3] = twice.tets[2][0];
  EXPECT_NE(error_of(twice).find("tet 2 names vertex"), std::string::npos);
  TetMesh empty;
  EXPECT_NE(error_of(empty).find("no tetrahedra"), std::string::npos);
  TetMesh nan = m;
  nan.positions(1, 5) = std::nan("");
  EXPECT_NE(error_of(nan).find("vertex 5 has a non-finite"), std::string::npos);
}

}  // namespace
}  // namespace pbd
