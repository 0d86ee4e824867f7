#include "pbd/io/mesh.hpp"

#include "edge_table.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

namespace pbd {
namespace {

using detail::half_edge_from;
using detail::half_edge_to;

// Numbers the undirected edges in the order the triangles first name them: edge[h] for every half-edge h. The
// half-edges are bucketed by their smaller endpoint (a counting sort, so each bucket keeps triangle order) and
// matched by their larger one inside the bucket. No hashing and no sort of all edges: linear in the triangles, a few
// compares per half-edge.
std::vector<std::uint32_t> edge_numbers(std::span<const std::array<Index, 3>> tris, std::uint32_t& edges) {
  const std::size_t halves = 3 * tris.size();
  if (halves >= std::numeric_limits<std::uint32_t>::max())
    throw Error(detail::message("mesh topology: ", tris.size(), " triangles are too many"));
  Index vertices = 0;
  for (const auto& t : tris) vertices = std::max({vertices, t[0] + 1, t[1] + 1, t[2] + 1});
  auto low = [&](std::size_t h) { return std::min(half_edge_from(tris, h), half_edge_to(tris, h)); };
  auto high = [&](std::size_t h) { return std::max(half_edge_from(tris, h), half_edge_to(tris, h)); };
  // bucket v is bucket[begin[v], begin[v + 1]): counted into begin[v + 2], summed, filled through begin[v + 1].
  std::vector<std::uint32_t> begin(std::size_t(vertices) + 2, 0);
  for (std::size_t h = 0; h < halves; ++h) ++begin[low(h) + 2];
  for (std::size_t v = 2; v < begin.size(); ++v) begin[v] += begin[v - 1];
  std::vector<std::uint32_t> bucket(halves);
  for (std::size_t h = 0; h < halves; ++h) bucket[begin[low(h) + 1]++] = std::uint32_t(h);
  // number[h]: first the first half-edge on h's edge, then (in place, in half-edge order) that edge's number.
  std::vector<std::uint32_t> number(halves);
  std::vector<std::pair<Index, std::uint32_t>> sorted;  // (larger endpoint, half-edge) of a big bucket
  for (std::size_t v = 0; v < vertices; ++v) {
    const std::uint32_t b = begin[v], e = begin[v + 1];
    if (e - b <= 32) {  // a usual vertex: compare with the earlier half-edges of its bucket
      for (std::uint32_t i = b; i < e; ++i) {
        std::uint32_t j = b;
        while (high(bucket[j]) != high(bucket[i])) ++j;  // stops at i at the latest
        number[bucket[i]] = bucket[j];
      }
    } else {  // a hub (the centre of a large fan): sort its bucket by the other endpoint, ties in triangle order
      sorted.clear();
      for (std::uint32_t i = b; i < e; ++i) sorted.emplace_back(high(bucket[i]), bucket[i]);
      std::sort(sorted.begin(), sorted.end());
      for (std::size_t i = 0; i < sorted.size(); ++i)
        number[sorted[i].second] = i > 0 && sorted[i].first == sorted[i - 1].first ? number[sorted[i - 1].second]
                                                                                     : sorted[i].second;
    }
  }
  edges = 0;
  for (std::size_t h = 0; h < halves; ++h) number[h] = number[h] == h ? edges++ : number[number[h]];
  return number;
}

}  // namespace

namespace detail {

EdgeTable edge_table(std::span<const std::array<Index, 3>> triangles) {
  std::uint32_t num_edges = 0;
  const std::vector<std::uint32_t> number = edge_numbers(triangles, num_edges);
  EdgeTable t;
  t.first.resize(num_edges);
  t.second.resize(num_edges);
  t.count.assign(num_edges, 0);
  for (std::size_t h = 0; h < number.size(); ++h) {
    const std::uint32_t e = number[h];
    if (t.count[e] == 0) t.first[e] = std::uint32_t(h);
    else if (t.count[e] == 1) t.second[e] = std::uint32_t(h);
    if (t.count[e] < 3) ++t.count[e];
  }
  return t;
}

}  // namespace detail

MeshTopology mesh_topology(std::span<const std::array<Index, 3>> triangles) {
  const detail::EdgeTable t = detail::edge_table(triangles);
  MeshTopology m;
  m.edges.reserve(t.size());
  std::size_t interior = 0;
  for (std::size_t e = 0; e < t.size(); ++e) {
    m.edges.push_back(t.edge(triangles, e));
    interior += t.count[e] == 2;
  }
  m.bending_pairs.reserve(interior);
  for (std::size_t e = 0; e < t.size(); ++e)
    if (t.count[e] == 2) m.bending_pairs.push_back(t.pair(triangles, e));
  return m;
}

std::vector<std::array<Index, 2>> mesh_edges(std::span<const std::array<Index, 3>> triangles) {
  return mesh_topology(triangles).edges;
}

std::vector<std::array<Index, 4>> mesh_bending_pairs(std::span<const std::array<Index, 3>> triangles) {
  return mesh_topology(triangles).bending_pairs;
}

}  // namespace pbd
