#pragma once
/// \file solver.hpp
/// Which solver World::step() runs, and how its parallel loops are cut.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace pbd {

/// The constraint solvers. All call the same projection functions.
enum class Solver : std::uint8_t {
  serial,          ///< reference: Gauss-Seidel over every constraint in insertion order, one thread
  serial_colored,  ///< Gauss-Seidel in color order on one thread: what `colored` computes, bit for bit
  colored,         ///< Gauss-Seidel color after color, each color's constraints in parallel (oneTBB)
  jacobi,          ///< every constraint reads the same positions; corrections averaged per particle, × ω
};

/// Name of a solver as the command line spells it: serial, serial-colored, colored, jacobi.
std::string_view name(Solver solver);
/// The solver with that name, if any.
std::optional<Solver> parse_solver(std::string_view name);

/// How the parallel solvers split work. Results never depend on these (only speed does).
struct ParallelConfig {
  std::size_t inline_below = 1024;  ///< a color (or particle range) smaller than this runs inline, no fork/join
  std::size_t min_grain = 256;      ///< smallest chunk handed to a task; grain = max(min_grain, n / (4·threads))
};

}  // namespace pbd
