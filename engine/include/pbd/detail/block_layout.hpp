#pragma once
/// \file detail/block_layout.hpp
/// The block layout of a constraint store (engine internals), what Solver::block sweeps. The particles are split
/// into blocks once (schedule.cpp, graph_coloring::partition); a constraint whose movable particles all lie in one
/// block b belongs to b's interior, group b of the store, in insertion order; the others cross blocks (the
/// boundary) and are colored with graph_coloring into the groups after the blocks. Two interiors never share a
/// movable particle, so the blocks run in parallel, each in order on one thread, with the bits of any other cut.
#include "pbd/detail/constraint_store.hpp"

#include <span>

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

/// Lays out every constraint of `s` for the block schedule: group b < blocks is block b's interior (insertion
/// order), the boundary constraints are colored with `options` into groups blocks, blocks + 1, ... Sets
/// s.sequential = blocks (every block keeps its group, even an empty one). Nothing changes when coloring throws.
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
  s.color = std::move(group);
  s.sequential = blocks;
  layout_by_color(s, by_user);
#ifndef NDEBUG
  s.validate(fixed, C::kName);  // debug builds: interiors disjoint, every boundary color independent
#endif
}

}  // namespace pbd::detail
