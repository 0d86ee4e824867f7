#include <array>
#include <string_view>
#include <utility>

#include "pbd/graph_coloring/color.hpp"

namespace pbd::coloring {

namespace {
constexpr std::array<std::pair<Algorithm, std::string_view>, 5> kNames{{
    {Algorithm::greedy_input, "input"},
    {Algorithm::greedy_largest_first, "largest-first"},
    {Algorithm::greedy_smallest_last, "smallest-last"},
    {Algorithm::greedy_random, "random"},
    {Algorithm::jones_plassmann, "jones-plassmann"},
}};
}  // namespace

std::string_view name(Algorithm algorithm) {
  for (const auto& [a, n] : kNames)
    if (a == algorithm) return n;
  return "unknown";
}

std::optional<Algorithm> parse_algorithm(std::string_view text) {
  for (const auto& [a, n] : kNames)
    if (n == text) return a;
  return std::nullopt;
}

}  // namespace pbd::coloring
