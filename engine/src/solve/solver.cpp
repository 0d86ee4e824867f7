#include "solver.hpp"

#include "chebyshev.hpp"
#include "schedule.hpp"
#include "sweep.hpp"

namespace pbd::detail {

template <class Real>
SolveReport solve(Model<Real>& model, State<Real>& state, Scratch<Real>& scratch, const StepParams<Real>& params,
           const ParallelConfig& config, double time, bool reverse) {
  const Solver solver = params.solver;
  const Schedule schedule = solver == Solver::serial ? Schedule::insertion
                            : uses_blocks(solver)     ? Schedule::blocks
                                                      : Schedule::colors;
  const Update update = solver == Solver::jacobi ? Update::jacobi : Update::in_place;
  const bool parallel = is_parallel(solver);
  if (schedule != Schedule::insertion) color_collisions(scratch.collisions);
  Sweeper<Real> sweeper(model, state, scratch, schedule, update, reverse, parallel, config);
  sweeper.omega = params.jacobi_omega;
  const bool accelerate = params.chebyshev.enabled && schedule != Schedule::insertion && params.iterations > 1;
  sweeper.keep_padded = !accelerate;
  sweeper.begin(time);
  Real* p = scratch.p.data();
  SolveReport report;
  if (!accelerate) {
    for (int it = 0; it < params.iterations; ++it) sweeper.sweep(p);
    sweeper.end(p);
    return report;
  }
  ChebyshevAccelerator<Real> chebyshev(params.chebyshev, params.iterations, model.num_particles(), state, scratch,
                                       parallel, config);
  for (int it = 0; it < params.iterations; ++it) {
    chebyshev.before(it, p);
    sweeper.sweep(p);
    chebyshev.after(it, p);
  }
  sweeper.end(p);
  report.chebyshev_fell_back = chebyshev.fell_back();
  report.chebyshev_estimate = double(chebyshev.estimate());
  return report;
}

template SolveReport solve(Model<float>&, State<float>&, Scratch<float>&, const StepParams<float>&, const ParallelConfig&,
                    double, bool);
template SolveReport solve(Model<double>&, State<double>&, Scratch<double>&, const StepParams<double>&,
                    const ParallelConfig&, double, bool);

}  // namespace pbd::detail
