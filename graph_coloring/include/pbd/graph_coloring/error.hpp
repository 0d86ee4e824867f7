#pragma once
/// \file error.hpp
/// The exception graph_coloring throws for invalid input.
#include <stdexcept>

namespace pbd::coloring {

/// Invalid input (offsets, node index, repeated node, option): what() names the item and node.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

}  // namespace pbd::coloring
