#include "pbd/graph_coloring/stats.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace pbd::coloring {

namespace {

// Most items among those kept by keep(i) sharing one non-fixed node (at least 1 if any is kept).
template <class Keep>
std::uint32_t most_sharing(const Hypergraph& g, Keep keep) {
  std::vector<std::uint32_t> count(g.num_nodes, 0);
  std::uint32_t best = 0;
  for (std::uint32_t i = 0; i < g.num_items(); ++i) {
    if (!keep(i)) continue;
    best = std::max(best, 1u);
    for (std::uint32_t node : g.item(i))
      if (!g.is_fixed(node)) best = std::max(best, ++count[node]);
  }
  return best;
}

}  // namespace

std::uint32_t color_lower_bound(const Hypergraph& g, std::uint32_t wide_threshold) {
  return most_sharing(g, [&](std::uint32_t i) { return g.offsets[i + 1] - g.offsets[i] <= wide_threshold; });
}

Stats compute_stats(const Hypergraph& g, const Coloring& c) {
  Stats s;
  s.num_items = g.num_items();
  s.num_colors = c.num_colors;
  s.num_wide = c.num_colors - c.num_regular_colors;
  s.seconds = c.seconds;
  s.lower_bound = most_sharing(g, [&](std::uint32_t i) { return c.color[i] < c.num_regular_colors; });
  if (c.num_regular_colors > 0) {
    std::uint64_t total = 0;
    s.min_batch = c.size_of(0);
    for (std::uint32_t k = 0; k < c.num_regular_colors; ++k) {
      s.min_batch = std::min(s.min_batch, c.size_of(k));
      s.max_batch = std::max(s.max_batch, c.size_of(k));
      total += c.size_of(k);
    }
    s.mean_batch = static_cast<double>(total) / c.num_regular_colors;
    s.max_over_mean = s.max_batch / s.mean_batch;
  }
  return s;
}

std::string format_stats(std::span<const NamedStats> rows) {
  std::size_t width = 4;
  for (const auto& r : rows) width = std::max(width, r.name.size());
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%-*s %10s %7s %7s %5s %9s %11s %9s %9s %10s\n", static_cast<int>(width), "name",
                "items", "colors", "bound", "wide", "min batch", "mean batch", "max batch", "max/mean", "time ms");
  out += line;
  for (const auto& r : rows) {
    const Stats& s = r.stats;
    std::snprintf(line, sizeof line, "%-*s %10u %7u %7u %5u %9u %11.1f %9u %9.3f %10.3f\n", static_cast<int>(width),
                  r.name.c_str(), s.num_items, s.num_colors, s.lower_bound, s.num_wide, s.min_batch, s.mean_batch,
                  s.max_batch, s.max_over_mean, s.seconds * 1e3);
    out += line;
  }
  return out;
}

}  // namespace pbd::coloring
