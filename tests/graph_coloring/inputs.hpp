#pragma once
/// \file inputs.hpp
/// Inputs for graph_coloring tests and benchmarks (the one copy both use): triangulated cloth grids
/// and random hypergraphs, generated with a fixed PRNG so they are identical everywhere.
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring::inputs {

/// splitmix64 stream: a small fixed PRNG.
struct Rng {
  std::uint64_t state;  ///< advances by the golden-ratio increment each draw
  /// Next 64 random bits.
  std::uint64_t next() {
    std::uint64_t x = (state += 0x9E3779B97F4A7C15ull);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  /// Uniform-enough integer in [0, n) (n > 0).
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>((next() >> 32) * n >> 32); }
};

/// An owning hypergraph; view() is valid while this object lives.
struct Graph {
  std::vector<std::uint32_t> offsets{0};  ///< CSR offsets
  std::vector<std::uint32_t> nodes;       ///< CSR node indices
  std::vector<std::uint8_t> fixed;        ///< empty or one flag per node
  std::uint32_t num_nodes = 0;            ///< node count

  /// Appends an item touching the given nodes.
  void add(std::initializer_list<std::uint32_t> item) {
    nodes.insert(nodes.end(), item.begin(), item.end());
    offsets.push_back(static_cast<std::uint32_t>(nodes.size()));
  }
  /// Non-owning view.
  [[nodiscard]] Hypergraph view() const { return Hypergraph{offsets, nodes, num_nodes, fixed}; }
  /// Number of items.
  [[nodiscard]] std::uint32_t num_items() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
};

/// Particle index of grid point (x, y) in an n x n grid.
inline std::uint32_t grid(std::uint32_t n, std::uint32_t x, std::uint32_t y) { return y * n + x; }

/// Unique edges (stretch constraints) of an n x n particle grid split into triangles along the
/// (x, y)-(x+1, y+1) diagonal, row by row: ~3 n^2 items, every interior particle in 6 of them.
/// With pin_corners, the two top corners are fixed (as a hanging cloth).
inline Graph cloth_edges(std::uint32_t n, bool pin_corners = false) {
  Graph g;
  g.num_nodes = n * n;
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      if (x + 1 < n) g.add({grid(n, x, y), grid(n, x + 1, y)});
      if (y + 1 < n) g.add({grid(n, x, y), grid(n, x, y + 1)});
      if (x + 1 < n && y + 1 < n) g.add({grid(n, x, y), grid(n, x + 1, y + 1)});
    }
  if (pin_corners) {
    g.fixed.assign(g.num_nodes, 0);
    g.fixed[grid(n, 0, n - 1)] = g.fixed[grid(n, n - 1, n - 1)] = 1;
  }
  return g;
}

/// Triangles (area constraints, 3 nodes) of the same grid.
inline Graph cloth_triangles(std::uint32_t n) {
  Graph g;
  g.num_nodes = n * n;
  for (std::uint32_t y = 0; y + 1 < n; ++y)
    for (std::uint32_t x = 0; x + 1 < n; ++x) {
      g.add({grid(n, x, y), grid(n, x + 1, y), grid(n, x + 1, y + 1)});
      g.add({grid(n, x, y), grid(n, x + 1, y + 1), grid(n, x, y + 1)});
    }
  return g;
}

/// Dihedral bending constraints (4 nodes: the shared edge and the two opposite corners) of the grid.
inline Graph cloth_bending(std::uint32_t n) {
  Graph g;
  g.num_nodes = n * n;
  for (std::uint32_t y = 0; y + 1 < n; ++y)
    for (std::uint32_t x = 0; x + 1 < n; ++x) {
      // diagonal edge inside the cell
      g.add({grid(n, x, y), grid(n, x + 1, y + 1), grid(n, x + 1, y), grid(n, x, y + 1)});
      // horizontal edge on top of the cell, shared with the cell above
      if (y + 2 < n) g.add({grid(n, x, y + 1), grid(n, x + 1, y + 1), grid(n, x, y), grid(n, x + 1, y + 2)});
      // vertical edge on the right of the cell, shared with the cell to the right
      if (x + 2 < n) g.add({grid(n, x + 1, y), grid(n, x + 1, y + 1), grid(n, x, y), grid(n, x + 2, y + 1)});
    }
  return g;
}

/// The items of a, then those of b, over the larger node count (e.g. a cloth's stretch and bending constraints);
/// fixed flags are a's.
inline Graph merge(const Graph& a, const Graph& b) {
  Graph g = a;
  g.num_nodes = a.num_nodes > b.num_nodes ? a.num_nodes : b.num_nodes;
  const std::uint32_t base = static_cast<std::uint32_t>(g.nodes.size());
  g.nodes.insert(g.nodes.end(), b.nodes.begin(), b.nodes.end());
  for (std::size_t i = 1; i < b.offsets.size(); ++i) g.offsets.push_back(base + b.offsets[i]);
  if (!g.fixed.empty()) g.fixed.resize(g.num_nodes, 0);
  return g;
}

/// num_items items of min_degree..max_degree distinct nodes among num_nodes (num_nodes >= max_degree),
/// with each node fixed with probability pinned_percent / 100.
inline Graph random_hypergraph(std::uint32_t num_items, std::uint32_t num_nodes, std::uint32_t min_degree,
                               std::uint32_t max_degree, std::uint32_t pinned_percent, std::uint64_t seed) {
  Rng rng{seed};
  Graph g;
  g.num_nodes = num_nodes;
  if (pinned_percent > 0) {
    g.fixed.resize(num_nodes);
    for (auto& f : g.fixed) f = rng.below(100) < pinned_percent ? 1 : 0;
  }
  g.offsets.reserve(static_cast<std::size_t>(num_items) + 1);
  g.nodes.reserve(static_cast<std::size_t>(num_items) * max_degree);
  for (std::uint32_t i = 0; i < num_items; ++i) {
    const std::uint32_t degree = min_degree + rng.below(max_degree - min_degree + 1);
    const std::size_t begin = g.nodes.size();
    while (g.nodes.size() - begin < degree) {
      const std::uint32_t v = rng.below(num_nodes);
      bool repeated = false;
      for (std::size_t p = begin; p < g.nodes.size(); ++p) repeated = repeated || g.nodes[p] == v;
      if (!repeated) g.nodes.push_back(v);
    }
    g.offsets.push_back(static_cast<std::uint32_t>(g.nodes.size()));
  }
  return g;
}

}  // namespace pbd::coloring::inputs
