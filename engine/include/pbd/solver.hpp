#pragma once
/// \file solver.hpp
/// Which solver World::step() runs, and how its parallel loops are cut.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pbd {

/// The constraint solvers. All call the same projection functions.
enum class Solver : std::uint8_t {
  serial,          ///< reference: Gauss-Seidel over every constraint in insertion order, one thread
  serial_colored,  ///< Gauss-Seidel in color order on one thread: what `colored` computes, bit for bit
  colored,         ///< Gauss-Seidel color after color, each color's constraints in parallel (oneTBB)
  jacobi,          ///< every constraint reads the same positions; corrections summed with split masses, × ω
  block,           ///< block Gauss-Seidel: each block's interior in insertion order (color by color for a type
                   ///< with colored interiors: Neo-Hookean tets), the blocks in parallel (one parallel loop per
                   ///< sweep), then the constraints crossing blocks color by color (BlockOptions)
};

/// Every solver, in the order the command line lists them.
inline constexpr Solver kSolvers[] = {Solver::serial, Solver::serial_colored, Solver::colored, Solver::jacobi,
                                      Solver::block};

/// Whether a solver runs on the block layout (the others run on the color layout, or insertion order).
constexpr bool uses_blocks(Solver s) { return s == Solver::block; }
/// Whether a solver runs its loops in parallel (the others run on the calling thread).
constexpr bool is_parallel(Solver s) { return s == Solver::colored || s == Solver::jacobi || s == Solver::block; }

/// The order of the Gauss-Seidel sweeps (serial and colored solvers; Jacobi has no order). The types are always
/// visited in the same order (constraint_types.hpp, user types, volumes, contacts last), so the volumes and the
/// contacts have the last word in every sweep; what the order changes is the order within each type.
enum class SweepOrder : std::uint8_t {
  forward,    ///< every sub-step sweeps each type in insertion order (serial) or color 0 first (colored)
  symmetric,  ///< odd sub-steps sweep each type backwards (the colors too): a fixed order over constraints that
              ///< cannot all hold has a handedness that spins a closed body up, and alternating cancels it; it
              ///< costs convergence where the forward order runs down from the pins (docs/robustness.md)
};

/// Name of a solver as the command line spells it: serial, serial-colored, colored, jacobi, block.
std::string_view name(Solver solver);
/// The solver with that name, if any.
std::optional<Solver> parse_solver(std::string_view name);
/// Every solver's name, comma-separated ("serial, serial-colored, ..."), for messages and help.
std::string solver_names();

/// Name of a sweep order: forward, symmetric.
std::string_view name(SweepOrder order);
/// The sweep order with that name, if any.
std::optional<SweepOrder> parse_sweep_order(std::string_view name);

/// How the particles are split into blocks for Solver::block. Part of the model, not of the machine: the blocks
/// decide the order of the projections (so the results), and they never depend on the thread count.
struct BlockOptions {
  std::size_t constraints_per_block = 1024;  ///< aim of the partition: about this many constraints per block, ≥ 1
  bool use_metis = true;  ///< true: METIS k-way on the particles' adjacency; false: ranges of particle indices
};

/// How the parallel solvers split work. Results never depend on these (only speed does).
struct ParallelConfig {
  std::size_t inline_below = 1024;  ///< a color (or particle range) smaller than this runs on one thread (no fork, no team)
  std::size_t min_grain = 256;      ///< smallest chunk handed to a task; grain = max(min_grain, n / (4·threads))
};

}  // namespace pbd
