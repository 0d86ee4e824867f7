// Shape-matching clusters from a tet mesh (pbd/io/shape_match_clusters.hpp): one per vertex, the vertex and its 7
// nearest neighbours through the tets, nearest first with ties by index; small or split meshes refused.
#include "error_checks.hpp"
#include "pbd/io/shape_match_clusters.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace pbd {
namespace {

using Clusters = std::vector<std::array<Index, 8>>;

// Vertices that share a tet with v.
std::set<Index> one_ring(const TetMesh& mesh, Index v) {
  std::set<Index> ring;
  for (const auto& t : mesh.tets)
    if (std::find(t.begin(), t.end(), v) != t.end()) ring.insert(t.begin(), t.end());
  ring.erase(v);
  return ring;
}

double distance2(const TetMesh& mesh, Index a, Index b) {
  return (mesh.positions.col(a) - mesh.positions.col(b)).squaredNorm();
}

// Every cluster of a 4 × 3 × 3 box of unit cubes (whole numbers: equal distances are equal, ties are ties): its own
// vertex first, 8 distinct vertices, the others nearest first (ties by index), from the 1-ring when it has 7 or more (then no vertex of the 1-ring left out is nearer than the farthest
// taken) and else from the 1- and 2-rings. The same clusters on a second call.
TEST(ShapeMatchClusters, BoxClustersAreEachVertexAndItsNearestNeighbours) {
  const TetMesh mesh = tet_box_mesh({4, 3, 3}, {4.0, 3.0, 3.0});
  const Clusters clusters = shape_match_clusters(mesh);
  ASSERT_EQ(clusters.size(), std::size_t(mesh.num_vertices()));
  int from_two_rings = 0;
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    const auto& c = clusters[v];
    SCOPED_TRACE(v);
    EXPECT_EQ(c[0], v);
    EXPECT_EQ(std::set<Index>(c.begin(), c.end()).size(), 8u);
    for (int i = 2; i < 8; ++i) {
      const double a = distance2(mesh, v, c[std::size_t(i) - 1]), b = distance2(mesh, v, c[std::size_t(i)]);
      EXPECT_TRUE(a < b || (a == b && c[std::size_t(i) - 1] < c[std::size_t(i)])) << "order at " << i;
    }
    const std::set<Index> ring = one_ring(mesh, v);
    if (ring.size() >= 7) {
      for (int i = 1; i < 8; ++i) EXPECT_TRUE(ring.count(c[std::size_t(i)])) << c[std::size_t(i)] << " not in the 1-ring";
      const double farthest = distance2(mesh, v, c[7]);
      for (Index n : ring) {
        if (std::find(c.begin(), c.end(), n) == c.end()) {
          EXPECT_GE(distance2(mesh, v, n), farthest) << n;
        }
      }
    } else {
      ++from_two_rings;
      for (int i = 1; i < 8; ++i) {
        bool near = ring.count(c[std::size_t(i)]) > 0;
        for (Index n : ring) near = near || one_ring(mesh, n).count(c[std::size_t(i)]) > 0;
        EXPECT_TRUE(near) << c[std::size_t(i)] << " beyond the 2-ring";
      }
    }
  }
  EXPECT_GT(from_two_rings, 0) << "some box corners have a 1-ring of 4";
  // Vertex (i, j, k) is i + 5j + 20k. The corner at the origin: its cube's corners, by distance 1, √2, √3.
  EXPECT_EQ(clusters[0], (std::array<Index, 8>{0, 1, 5, 20, 6, 21, 25, 26}));
  EXPECT_EQ(shape_match_clusters(mesh), clusters);
}

// One unit cube (8 vertices): a corner off the cut's diagonal, (1, 0, 0) = vertex 1, is in 2 of the 6 tets, its
// 1-ring 4 vertices, so its cluster reaches into the 2-ring: all 8, by distance 1, √2, √3 and index.
TEST(ShapeMatchClusters, AFewNeighboursReachIntoTheTwoRing) {
  const TetMesh mesh = tet_box_mesh({1, 1, 1}, {1.0, 1.0, 1.0});
  ASSERT_EQ(one_ring(mesh, 1).size(), 4u);
  const Clusters clusters = shape_match_clusters(mesh);
  EXPECT_EQ(clusters[1], (std::array<Index, 8>{1, 0, 3, 5, 2, 4, 7, 6}));
  EXPECT_EQ(clusters[0], (std::array<Index, 8>{0, 1, 2, 4, 3, 5, 6, 7}));
}

// Fewer than 8 vertices, or a vertex joined to fewer than 7 others (two separate tets of 4), are refused.
TEST(ShapeMatchClusters, SmallOrSplitMeshesAreRefused) {
  TetMesh one;
  one.positions = Matrix3X<double>(3, 4);
  one.positions << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  one.tets = {{0, 1, 2, 3}};
  EXPECT_EQ(test::error_of([&] { shape_match_clusters(one); }),
            "shape_match_clusters: a cluster is 8 vertices; the mesh has 4");
  TetMesh two;
  two.positions = Matrix3X<double>(3, 8);
  two.positions << one.positions, one.positions.array() + 5.0;
  two.tets = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  EXPECT_EQ(test::error_of([&] { shape_match_clusters(two); }),
            "shape_match_clusters: vertex 0 is joined through the tets to only 3 other vertices; a cluster needs 7");
}

}  // namespace
}  // namespace pbd
