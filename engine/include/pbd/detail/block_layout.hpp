#pragma once
/// \file detail/block_layout.hpp
/// The block layout of a constraint store (engine internals), what Solver::block sweeps. The particles are split
/// into blocks once (schedule.cpp, graph_coloring::partition); a constraint whose movable particles all lie in one
/// block b belongs to b's interior, group b of the store, in insertion order (or, for a type with colored
/// interiors (traits.hpp), colored with graph_coloring within the block and laid out color by color: the store's
/// runs); the others cross blocks (the boundary) and are colored with graph_coloring into the groups after the
/// blocks. Two interiors never share a movable particle, so the blocks run in parallel, each in order on one thread,
/// with the bits of any other cut.
#include "pbd/constraints/traits.hpp"
#include "pbd/detail/constraint_store.hpp"

#include <algorithm>
#include <span>
#include <utility>

namespace pbd::detail {

/// "Not in any block": a particle added after the partition (its constraints are boundary ones).
inline constexpr std::uint32_t kNoBlock = ~std::uint32_t(0);

/// The interior a constraint belongs to: the block all its movable particles lie in, or kNoBlock when they lie in
/// more than one block, in none, or the constraint has no movable particle.
template <class C>
std::uint32_t interior_block(const C& c, const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block) {
  std::uint32_t b = kNoBlock;
  for (Index p : c.particles) {
    if (p < fixed.size() && fixed[p]) continue;
    const std::uint32_t pb = p < block.size() ? block[p] : kNoBlock;
    if (pb == kNoBlock || (b != kNoBlock && pb != b)) return kNoBlock;
    b = pb;
  }
  return b;
}

/// The block a boundary constraint is filed under: the smallest block among its movable particles (kNoBlock when
/// none lies in a block).
template <class C>
std::uint32_t first_block(const C& c, const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block) {
  std::uint32_t b = kNoBlock;
  for (Index p : c.particles)
    if (!(p < fixed.size() && fixed[p]) && p < block.size()) b = std::min(b, block[p]);
  return b;
}

/// Puts each boundary color of `s` (groups from s.sequential on) in order of first_block, ties in insertion order.
/// A color's constraints share no movable particle, so their order changes no bit; it lets a thread that runs
/// blocks [b0, b1) take the constraints filed under them as one range (sweep.hpp), so the boundary's particles stay
/// in the cache of the thread that projected their interiors.
template <class C>
void sort_boundary_by_block(Store<C>& s, const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block) {
  const Index n = Index(s.items.size());
  std::vector<Index> user_at(n);
  for (Index u = 0; u < n; ++u) user_at[s.slot[u]] = u;
  std::vector<std::pair<std::uint32_t, Index>> keyed;
  std::vector<C> items;
  for (Index c = s.sequential; c < s.num_colors(); ++c) {
    const Index b = s.offsets[c], e = s.offsets[c + 1];
    keyed.clear();
    for (Index i = b; i < e; ++i) keyed.emplace_back(first_block(s.items[i], fixed, block), user_at[i]);
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    items.assign(s.items.begin() + b, s.items.begin() + e);
    for (Index k = 0; k < e - b; ++k) {
      const Index u = keyed[k].second;
      s.items[b + k] = items[s.slot[u] - b];
      s.slot[u] = b + k;
    }
  }
}

/// Colors each block's interior of `s` on its own with `options` and lays it out color by color (by insertion
/// index within a color), setting s.runs and s.block_runs. The groups and the boundary are untouched.
template <class C>
void color_interiors(Store<C>& s, const std::vector<std::uint8_t>& fixed, const coloring::Options& options) {
  const Index blocks = s.sequential;
  std::vector<Index> user_at(s.items.size());
  for (Index u = 0; u < Index(s.items.size()); ++u) user_at[s.slot[u]] = u;
  std::vector<Index> runs, block_runs(std::size_t(blocks) + 1, 0);
  std::vector<C> items;
  std::vector<Index> users;
  ConstraintGraph graph;
  for (Index b = 0; b < blocks; ++b) {
    block_runs[b] = Index(runs.size());
    const Index begin = s.offsets[b], end = s.offsets[b + 1];
    if (begin == end) continue;
    items.assign(s.items.begin() + begin, s.items.begin() + end);  // by insertion index (layout_by_color)
    users.assign(user_at.begin() + begin, user_at.begin() + end);
    coloring::Coloring col;
    try {
      fill_constraint_graph(std::span<const C>(items), fixed, graph);
      col = coloring::color(graph.view(), options);
    } catch (const coloring::Error& e) {
      throw Error(std::string("coloring the interior of block ") + std::to_string(b) + " of " + C::kName +
                  " constraints: " + e.what());
    }
    for (std::uint32_t c = 0; c < col.num_colors; ++c) runs.push_back(begin + Index(col.color_offsets[c]));
    for (Index k = 0; k < end - begin; ++k) {  // by color, insertion order within one (graph_coloring's items)
      const Index from = Index(col.items[k]);
      s.items[begin + k] = items[from];
      s.slot[users[from]] = begin + k;
    }
  }
  block_runs[blocks] = Index(runs.size());
  runs.push_back(s.offsets[blocks]);
  s.runs = std::move(runs);
  s.block_runs = std::move(block_runs);
}

/// Lays out every constraint of `s` for the block schedule: group b < blocks is block b's interior (insertion
/// order, or color by color for a type with colored interiors), the boundary constraints are colored with
/// `options` into groups blocks, blocks + 1, ... Sets s.sequential = blocks (every block keeps its group, even an
/// empty one). Nothing changes when coloring throws.
template <class C>
void lay_out_blocks(Store<C>& s, const std::vector<std::uint8_t>& fixed, std::span<const std::uint32_t> block,
                    Index blocks, const coloring::Options& options) {
  if (s.empty()) return s.clear();
  std::vector<C> by_user = s.in_insertion_order();
  std::vector<Index> group(by_user.size());
  std::vector<C> boundary;
  std::vector<Index> boundary_user;
  for (Index u = 0; u < Index(by_user.size()); ++u) {
    const std::uint32_t b = interior_block(by_user[u], fixed, block);
    if (b != kNoBlock) {
      assert(b < blocks);
      group[u] = b;
    } else {
      boundary.push_back(by_user[u]);
      boundary_user.push_back(u);
    }
  }
  if (!boundary.empty()) {
    coloring::Coloring col;
    try {
      const ConstraintGraph graph = constraint_graph(std::span<const C>(boundary), fixed);
      col = coloring::color(graph.view(), options);
    } catch (const coloring::Error& e) {
      throw Error(std::string("coloring the block boundary of ") + C::kName + " constraints: " + e.what());
    }
    for (std::size_t k = 0; k < boundary.size(); ++k) group[boundary_user[k]] = blocks + Index(col.color[k]);
  }
  Store<C> before;
  if constexpr (colored_interiors<C>()) before = s;  // color_interiors may throw after the layout
  s.color = std::move(group);
  s.sequential = blocks;
  layout_by_color(s, by_user);
  sort_boundary_by_block(s, fixed, block);
  if constexpr (colored_interiors<C>()) {
    try {
      color_interiors(s, fixed, options);
    } catch (...) {
      s = std::move(before);
      throw;
    }
  }
#ifndef NDEBUG
  s.validate(fixed, C::kName);  // debug builds: interiors disjoint, every boundary color independent
#endif
}

}  // namespace pbd::detail
