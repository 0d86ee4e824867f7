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
  jacobi,          ///< every constraint reads the same positions; corrections summed with split masses, × ω
};

/// The order of the Gauss-Seidel sweeps (serial and colored solvers; Jacobi has no order). The types are always
/// visited in the same order (constraint_types.hpp, user types, volumes, contacts last), so the volumes and the
/// contacts have the last word in every sweep; what the order changes is the order within each type.
enum class SweepOrder : std::uint8_t {
  forward,    ///< every sub-step sweeps each type in insertion order (serial) or color 0 first (colored)
  symmetric,  ///< odd sub-steps sweep each type backwards (the colors too): a fixed order over constraints that
              ///< cannot all hold has a handedness that spins a closed body up, and alternating cancels it; it
              ///< costs convergence where the forward order runs down from the pins (docs/robustness.md)
};

/// Name of a solver as the command line spells it: serial, serial-colored, colored, jacobi.
std::string_view name(Solver solver);
/// The solver with that name, if any.
std::optional<Solver> parse_solver(std::string_view name);

/// Name of a sweep order: forward, symmetric.
std::string_view name(SweepOrder order);
/// The sweep order with that name, if any.
std::optional<SweepOrder> parse_sweep_order(std::string_view name);

/// How the parallel solvers split work. Results never depend on these (only speed does).
struct ParallelConfig {
  std::size_t inline_below = 1024;  ///< a color (or particle range) smaller than this runs inline, no fork/join
  std::size_t min_grain = 256;      ///< smallest chunk handed to a task; grain = max(min_grain, n / (4·threads))
};

}  // namespace pbd
