#pragma once
/// \file color.hpp
/// Entry point: color a hypergraph's items with the algorithm the caller picks.
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "pbd/graph_coloring/coloring.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"

namespace pbd::coloring {

/// How items are colored. The greedy ones are serial first-fit in the named order; every order
/// breaks ties by item index.
enum class Algorithm : std::uint8_t {
  greedy_input,           ///< first-fit in item-index order (fastest)
  greedy_largest_first,   ///< first-fit, items with most conflicts first
  greedy_smallest_last,   ///< first-fit in smallest-last (degeneracy) order (Matula–Beck)
  greedy_random,          ///< first-fit in a seeded random order
  jones_plassmann,        ///< parallel (oneTBB) Jones–Plassmann with seeded random priorities; equals greedy_random for the same seed
};

/// Every algorithm, in declaration order.
inline constexpr Algorithm all_algorithms[] = {Algorithm::greedy_input, Algorithm::greedy_largest_first,
                                               Algorithm::greedy_smallest_last, Algorithm::greedy_random,
                                               Algorithm::jones_plassmann};

/// Command-line name of an algorithm: input, largest-first, smallest-last, random, jones-plassmann.
[[nodiscard]] std::string_view name(Algorithm algorithm);
/// The algorithm with that command-line name, if any.
[[nodiscard]] std::optional<Algorithm> parse_algorithm(std::string_view name);

/// What color() does.
struct Options {
  Algorithm algorithm = Algorithm::greedy_input;  ///< coloring algorithm
  bool balance = true;                            ///< then even out batch sizes (see balance())
  double balance_target = 1.1;                    ///< balancing stops once largest batch <= target x mean batch
  std::uint64_t seed = 0;                         ///< seed of the random order / priorities
  std::uint32_t wide_threshold = 64;              ///< items touching more nodes than this are wide (own color each)
};

/// Validates the input (throws Error), colors it, and groups items by color. The result depends only
/// on the input and options, never on the number of threads.
[[nodiscard]] Coloring color(const Hypergraph& graph, const Options& options = {});

/// Continues a first-fit coloring with every item of `graph`, in index order, against colors already in use:
/// used[node] has bit c set when color c is taken at that node (num_nodes entries). Each item takes the lowest color
/// below max_colors (at most 64) free at all its non-fixed nodes, written to color[item], and marks it in `used`.
/// Returns false as soon as an item finds no such color (the caller then colors everything anew). O(incidences);
/// no validation beyond what the caller guarantees (node indices below num_nodes).
bool first_fit_extend(const Hypergraph& graph, std::span<std::uint64_t> used, std::uint32_t max_colors,
                      std::span<std::uint32_t> color);

/// Moves items from large regular colors to small ones where they fit, never adding a color, until
/// the largest batch is at most target x mean batch or nothing more moves. Deterministic; keeps the
/// coloring proper and regroups it. Returns the achieved largest / mean batch size.
double balance(const Hypergraph& graph, Coloring& coloring, double target = 1.1);

}  // namespace pbd::coloring
