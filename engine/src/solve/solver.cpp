#include "solver.hpp"

#include "schedule.hpp"
#include "sweep.hpp"

namespace pbd::detail {

template <class Real>
void solve(Model<Real>& model, State<Real>& state, Scratch<Real>& scratch, const StepParams<Real>& params,
           const ParallelConfig& config, double time, bool reverse) {
  const Solver solver = params.solver;
  const Schedule schedule = solver == Solver::serial ? Schedule::insertion : Schedule::colors;
  const Update update = solver == Solver::jacobi ? Update::jacobi : Update::in_place;
  const bool parallel = solver == Solver::colored || solver == Solver::jacobi;
  if (schedule == Schedule::colors) color_collisions(scratch.collisions);
  Sweeper<Real> sweeper(model, state, scratch, schedule, update, reverse, parallel, config);
  sweeper.omega = params.jacobi_omega;
  sweeper.begin(time);
  Real* p = scratch.p.data();
  for (int it = 0; it < params.iterations; ++it) sweeper.sweep(p);
  sweeper.end(p);
}

template void solve(Model<float>&, State<float>&, Scratch<float>&, const StepParams<float>&, const ParallelConfig&,
                    double, bool);
template void solve(Model<double>&, State<double>&, Scratch<double>&, const StepParams<double>&,
                    const ParallelConfig&, double, bool);

}  // namespace pbd::detail
