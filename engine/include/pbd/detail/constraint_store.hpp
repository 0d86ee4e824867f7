#pragma once
/// \file detail/constraint_store.hpp
/// One constraint type's constraints, stored once (engine internals; a host needs it only through World and
/// ConstraintView). Until the first coloring the items sit in insertion order; coloring lays them out group by group
/// (by insertion index within a group) and keeps the map from the user's index to the stored position, which the
/// serial reference solver also follows to visit them in insertion order. A group is a color (no two of its
/// constraints share a movable particle) or, in the block layout (block_layout.hpp), one of the leading
/// `sequential` groups: a block's interior, projected in order by one task, sharing no movable particle with any
/// other block's interior. Constraints added after a coloring sit at
/// the end, uncolored, until the next colored step gives them "tail" colors after the others (first fit, see
/// color_tail) without touching the rest.
#include "pbd/error.hpp"
#include "pbd/types.hpp"

#include <pbd/graph_coloring/color.hpp>
#include <pbd/graph_coloring/error.hpp>

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pbd::detail {

/// The constraints of one fixed-arity type C (built in or user-defined).
template <class C> struct Store {
  using value_type = C;          ///< the constraint type
  std::vector<C> items;          ///< stored order: insertion order until colored, then color by color
  std::vector<Index> slot;       ///< user index → position in items; empty while items are in insertion order
  std::vector<Index> color;      ///< user index → group (a color, or a block below `sequential`); empty while uncolored
  std::vector<Index> offsets;    ///< group c is items[offsets[c], offsets[c + 1]); empty while uncolored
  Index sequential = 0;          ///< block layout: groups [0, sequential) are the blocks' interiors (kept, even empty)
  /// Block layout of a type with colored interiors (traits.hpp): each interior is laid out color by color, and
  /// block b's colors are the runs k in [block_runs[b], block_runs[b + 1]), run k being items[runs[k], runs[k + 1]).
  /// Empty otherwise.
  std::vector<Index> runs;
  std::vector<Index> block_runs;  ///< sequential + 1 entries when runs is not empty
  /// Constraints colored since the last full coloring live in tail colors [tail_color, num_colors()), user indices
  /// from tail_item on; tail_used has, per particle, bit k set when tail color tail_color + k is at it.
  static constexpr Index kNoTail = ~Index(0);
  Index tail_color = kNoTail;              ///< first tail color (kNoTail: none)
  Index tail_item = 0;                     ///< first user index in the tail
  std::vector<std::uint64_t> tail_used;    ///< per particle: tail colors in use

  std::size_t size() const { return items.size(); }                                      ///< number of constraints
  bool empty() const { return items.empty(); }                                           ///< true when there are none
  Index num_colors() const { return offsets.empty() ? 0 : Index(offsets.size() - 1); }  ///< colors laid out
  bool up_to_date() const { return color.size() == items.size(); }  ///< every constraint has a color
  /// Stored position of the constraint with user index u.
  Index stored(Index u) const { return slot.empty() ? u : slot[u]; }
  /// The constraint with user index u.
  const C& at(Index u) const { return items[stored(u)]; }
  /// Appends a constraint (user index size()); after a coloring it waits uncolored at the end.
  void append(const C& c) {
    if (!slot.empty() || !color.empty()) {
      if (slot.empty()) slot = identity(Index(items.size()));
      slot.push_back(Index(items.size()));
    }
    items.push_back(c);
  }
  /// Removes every constraint and the coloring.
  void clear() {
    items.clear();
    slot.clear();
    color.clear();
    offsets.clear();
    sequential = 0;
    runs.clear();
    block_runs.clear();
    tail_color = kNoTail;
    tail_used.clear();
  }
  /// Forgets the coloring: items back in insertion order.
  void uncolor() {
    items = in_insertion_order();
    slot.clear();
    color.clear();
    offsets.clear();
    sequential = 0;
    runs.clear();
    block_runs.clear();
    tail_color = kNoTail;
    tail_used.clear();
  }
  /// The items in insertion (user) order.
  std::vector<C> in_insertion_order() const {
    if (slot.empty()) return items;
    std::vector<C> out(items.size());
    for (Index u = 0; u < Index(items.size()); ++u) out[u] = items[slot[u]];
    return out;
  }
  static std::vector<Index> identity(Index n) {
    std::vector<Index> v(n);
    for (Index i = 0; i < n; ++i) v[i] = i;
    return v;
  }
  /// Checks the layout (throws pbd::Error naming what is wrong): the map is a permutation, colors are contiguous
  /// ranges matching `color`, and no two constraints of one color share a particle not in `fixed`.
  void validate(const std::vector<std::uint8_t>& fixed, const char* name) const;
  /// validate()'s part for the runs: they tile the interiors block by block, and no two constraints of a run share
  /// a movable particle.
  void validate_runs(const std::vector<std::uint8_t>& fixed, const std::string& what) const;
};

/// Places the constraints with user indices [first_user, n) of `by_user` (insertion order, n = by_user.size()) into
/// s.items grouped by their colors (all in [first_color, first_color + colors)), by user index within a color,
/// from s.offsets[first_color] on; sets the offsets after it and the slots.
template <class C>
void place_by_color(Store<C>& s, const std::vector<C>& by_user, Index first_user, Index first_color, Index colors) {
  const Index n = Index(by_user.size());
  std::vector<Index> count(colors, 0);
  for (Index u = first_user; u < n; ++u) ++count[s.color[u] - first_color];
  for (Index c = 0; c < colors; ++c) s.offsets[first_color + c + 1] = s.offsets[first_color + c] + count[c];
  assert(s.offsets[first_color + colors] == n - first_user + s.offsets[first_color]);
  std::vector<Index> next(s.offsets.begin() + first_color, s.offsets.begin() + first_color + colors);
  s.items.resize(n);
  s.slot.resize(n);
  for (Index u = first_user; u < n; ++u) {
    const Index at = next[s.color[u] - first_color]++;
    s.slot[u] = at;
    s.items[at] = by_user[u];
  }
}

/// Lays out `by_user` (the constraints in insertion order) by the groups in s.color (one per constraint): grouped by
/// group, by user index within a group; empty colors are dropped and the others renumbered in order (the
/// s.sequential block groups are kept, empty or not, so block b stays group b); no tail.
template <class C> void layout_by_color(Store<C>& s, const std::vector<C>& by_user) {
  const Index n = Index(by_user.size());
  Index colors = s.sequential;
  for (Index c : s.color) colors = std::max(colors, c + 1);
  std::vector<Index> count(colors, 0), renumber(colors, 0);
  for (Index c : s.color) ++count[c];
  Index used = 0;
  for (Index c = 0; c < colors; ++c) renumber[c] = (count[c] || c < s.sequential) ? used++ : 0;
  for (Index& c : s.color) c = renumber[c];
  // Room for the tail that color_tail may add (at most 10%) without moving the arrays.
  const std::size_t room = std::size_t(n) + n / 10 + 16;
  s.items.reserve(room);
  s.slot.reserve(room);
  s.color.reserve(room);
  s.offsets.assign(std::size_t(used) + 1, 0);
  place_by_color(s, by_user, 0, 0, used);
  if (n == 0) {
    s.offsets.clear();
    s.sequential = 0;
  }
  s.runs.clear();  // the block layout colors the interiors again after this (block_layout.hpp)
  s.block_runs.clear();
  s.tail_color = Store<C>::kNoTail;
  s.tail_used.clear();
}

/// The conflict hypergraph of constraints (CSR: particles of each constraint), as graph_coloring reads it.
struct ConstraintGraph {
  std::vector<std::uint32_t> offsets;  ///< constraints + 1 entries
  std::vector<std::uint32_t> nodes;    ///< particles of each constraint, constraint after constraint
  std::span<const std::uint8_t> fixed; ///< 1 for pinned particles (never written, so never in conflict)
  std::uint32_t num_particles = 0;     ///< number of particles
  /// Non-owning view for graph_coloring (valid while this object and `fixed` live).
  coloring::Hypergraph view() const { return {offsets, nodes, num_particles, fixed}; }
};

/// Fills g with the hypergraph of fixed-arity constraints `items`, reusing g's buffers.
template <class C>
void fill_constraint_graph(std::span<const C> items, const std::vector<std::uint8_t>& fixed, ConstraintGraph& g) {
  g.num_particles = std::uint32_t(fixed.size());
  g.fixed = fixed;
  g.offsets.clear();
  g.offsets.reserve(items.size() + 1);
  g.offsets.push_back(0);
  g.nodes.clear();
  g.nodes.reserve(items.size() * C::kArity);
  for (const C& c : items) {
    for (Index p : c.particles) g.nodes.push_back(p);
    g.offsets.push_back(std::uint32_t(g.nodes.size()));
  }
}

/// The hypergraph of fixed-arity constraints `items`.
template <class C>
ConstraintGraph constraint_graph(std::span<const C> items, const std::vector<std::uint8_t>& fixed) {
  ConstraintGraph g;
  fill_constraint_graph(items, fixed, g);
  return g;
}

/// Colors every constraint of `s` anew with graph_coloring (pinned particles never conflict) and lays it out.
template <class C> void color_all(Store<C>& s, const std::vector<std::uint8_t>& fixed, const coloring::Options& options) {
  if (s.empty()) return s.clear();
  s.sequential = 0;
  // Never colored: the items are already in insertion order, so take them instead of copying them.
  const bool in_order = s.slot.empty();
  std::vector<C> by_user = in_order ? std::move(s.items) : s.in_insertion_order();
  coloring::Coloring col;
  try {  // on failure the store is as it was
    const ConstraintGraph graph = constraint_graph(std::span<const C>(by_user), fixed);
    col = coloring::color(graph.view(), options);
  } catch (const coloring::Error& e) {
    if (in_order) s.items = std::move(by_user);
    throw Error(std::string("coloring ") + C::kName + " constraints: " + e.what());
  } catch (...) {
    if (in_order) s.items = std::move(by_user);
    throw;
  }
  s.color.assign(col.color.begin(), col.color.end());
  layout_by_color(s, by_user);
#ifndef NDEBUG
  s.validate(fixed, C::kName);  // debug builds: every color independent, the map a permutation
#endif
}

/// Colors the constraints appended since `s` was last laid out, without touching the others: they go into tail
/// colors after the existing ones, first fit among the tail colors only (graph_coloring::first_fit_extend; colors
/// run one after the other, so a tail constraint may share particles with any earlier color). Work is proportional
/// to the appended constraints (plus one per-particle table the first time). Returns false when the tail would pass
/// 8 colors or 10% of the constraints: the caller then colors everything anew, which keeps the color count low.
template <class C> bool color_tail(Store<C>& s, const std::vector<std::uint8_t>& fixed) {
  constexpr Index kMaxTailColors = 8;
  if (s.sequential != 0) return false;  // the block layout lays out again instead (block_layout.hpp)
  const Index first = Index(s.color.size()), n = Index(s.items.size());
  if (s.tail_color == Store<C>::kNoTail) {
    s.tail_color = s.num_colors();
    s.tail_item = first;
    s.tail_used.assign(fixed.size(), 0);
  }
  s.tail_used.resize(fixed.size(), 0);
  if (std::size_t(n - s.tail_item) * 10 > std::size_t(n)) return false;
  // The appended constraints sit at the end of items, in insertion order.
  const std::span<const C> added(s.items.data() + (s.slot.empty() ? first : s.slot[first]), n - first);
  const ConstraintGraph graph = constraint_graph(added, fixed);
  std::vector<std::uint32_t> tail(added.size());
  if (!coloring::first_fit_extend(graph.view(), s.tail_used, kMaxTailColors, tail)) return false;
  Index tail_colors = s.num_colors() - s.tail_color;
  for (std::uint32_t c : tail) {
    s.color.push_back(s.tail_color + c);
    tail_colors = std::max(tail_colors, Index(c + 1));
  }
  // Lay out the tail only: its constraints by color, then user index, after the untouched colors.
  std::vector<C> by_user(n);
  for (Index u = s.tail_item; u < n; ++u) by_user[u] = s.at(u);
  if (s.slot.empty()) s.slot = Store<C>::identity(n);
  s.offsets.resize(std::size_t(s.tail_color) + tail_colors + 1, 0);
  place_by_color(s, by_user, s.tail_item, s.tail_color, tail_colors);
  assert(s.up_to_date() && s.offsets.back() == n);
#ifndef NDEBUG
  s.validate(fixed, C::kName);
#endif
  return true;
}

/// Removes the constraints whose user index has drop[u] set; the others keep their order. Colored and up to date
/// (and no interior colored by runs, whose order this would lose): they keep their colors too (laid out again,
/// nothing recolored); otherwise the store is left uncolored.
/// Returns false when it left a colored store uncolored (the caller recolors everything at the next colored step).
template <class C> bool erase(Store<C>& s, const std::vector<std::uint8_t>& drop) {
  const bool keep_colors = !s.offsets.empty() && s.up_to_date() && s.runs.empty();
  const Index n = Index(s.items.size());
  std::vector<C> kept;
  kept.reserve(n);
  std::vector<Index> colors;
  for (Index u = 0; u < n; ++u)
    if (!drop[u]) {
      kept.push_back(s.at(u));
      if (keep_colors) colors.push_back(s.color[u]);
    }
  if (keep_colors) {
    s.color = std::move(colors);
    layout_by_color(s, kept);
    return true;
  }
  const bool was_colored = !s.color.empty();
  s.items = std::move(kept);
  s.slot.clear();
  s.color.clear();
  s.offsets.clear();
  s.sequential = 0;
  s.runs.clear();
  s.block_runs.clear();
  s.tail_color = Store<C>::kNoTail;
  s.tail_used.clear();
  return !was_colored;
}

template <class C> void Store<C>::validate(const std::vector<std::uint8_t>& fixed, const char* name) const {
  const std::string what = std::string("validate: ") + name + " store: ";
  const Index n = Index(items.size());
  if (!slot.empty()) {
    if (slot.size() != n) throw Error(what + "the index map has " + std::to_string(slot.size()) + " entries for " + std::to_string(n));
    std::vector<std::uint8_t> seen(n, 0);
    for (Index u = 0; u < n; ++u) {
      if (slot[u] >= n || seen[slot[u]]) throw Error(what + "the index map is not a permutation at " + std::to_string(u));
      seen[slot[u]] = 1;
    }
  }
  if (offsets.empty()) return;
  if (offsets.front() != 0 || offsets.back() > n) throw Error(what + "color ranges do not cover the items");
  if (sequential > num_colors()) throw Error(what + "more blocks than groups");
  std::vector<Index> owner(fixed.size(), ~Index(0));
  for (Index c = 0; c < num_colors(); ++c) {
    if (offsets[c] > offsets[c + 1]) throw Error(what + "group " + std::to_string(c) + " has a negative range");
    for (Index i = offsets[c]; i < offsets[c + 1]; ++i)
      for (Index p : items[i].particles) {
        if (p < fixed.size() && fixed[p]) continue;
        if (c < sequential) {  // a block's interior: its particles are in no other block's interior
          if (owner[p] != ~Index(0) && owner[p] != c)
            throw Error(what + "particle " + std::to_string(p) + " is in the interiors of blocks " +
                        std::to_string(owner[p]) + " and " + std::to_string(c));
        } else if (owner[p] == c) {
          throw Error(what + "particle " + std::to_string(p) + " appears twice in color " + std::to_string(c));
        }
        owner[p] = c;
      }
  }
  validate_runs(fixed, what);
  for (Index u = 0; u < Index(color.size()); ++u) {
    const Index i = stored(u);
    if (i < offsets.back() && !(color[u] < num_colors() && offsets[color[u]] <= i && i < offsets[color[u] + 1]))
      throw Error(what + "constraint " + std::to_string(u) + " is not in the range of its color " + std::to_string(color[u]));
  }
}

template <class C> void Store<C>::validate_runs(const std::vector<std::uint8_t>& fixed, const std::string& what) const {
  if (runs.empty()) return;
  if (block_runs.size() != std::size_t(sequential) + 1 || block_runs.front() != 0 ||
      block_runs.back() + 1 != Index(runs.size()))
    throw Error(what + "the interiors' runs do not match the blocks");
  for (Index b = 0; b < sequential; ++b) {
    if (block_runs[b] > block_runs[b + 1])
      throw Error(what + "block " + std::to_string(b) + " has a negative run count");
    if (runs[block_runs[b]] != offsets[b] || runs[block_runs[b + 1]] != offsets[b + 1])
      throw Error(what + "the runs of block " + std::to_string(b) + " do not cover its interior");
  }
  std::vector<Index> owner(fixed.size(), ~Index(0));
  for (Index k = 0; k + 1 < Index(runs.size()); ++k) {
    if (runs[k] > runs[k + 1]) throw Error(what + "run " + std::to_string(k) + " has a negative range");
    for (Index i = runs[k]; i < runs[k + 1]; ++i)
      for (Index p : items[i].particles) {
        if (p < fixed.size() && fixed[p]) continue;
        if (owner[p] == k)
          throw Error(what + "particle " + std::to_string(p) + " appears twice in interior run " + std::to_string(k));
        owner[p] = k;
      }
  }
}

}  // namespace pbd::detail
