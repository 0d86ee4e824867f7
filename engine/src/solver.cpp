#include "pbd/solver.hpp"

namespace pbd {

std::string_view name(Solver solver) {
  switch (solver) {
    case Solver::serial: return "serial";
    case Solver::serial_colored: return "serial-colored";
    case Solver::colored: return "colored";
    case Solver::jacobi: return "jacobi";
    case Solver::block: return "block";
  }
  return "?";
}

std::optional<Solver> parse_solver(std::string_view n) {
  for (Solver s : kSolvers)
    if (name(s) == n) return s;
  return std::nullopt;
}

std::string solver_names() {
  std::string out;
  for (Solver s : kSolvers) out += (out.empty() ? "" : ", ") + std::string(name(s));
  return out;
}

std::string_view name(SweepOrder order) {
  switch (order) {
    case SweepOrder::forward: return "forward";
    case SweepOrder::symmetric: return "symmetric";
  }
  return "?";
}

std::optional<SweepOrder> parse_sweep_order(std::string_view n) {
  for (SweepOrder o : {SweepOrder::forward, SweepOrder::symmetric})
    if (name(o) == n) return o;
  return std::nullopt;
}

}  // namespace pbd
