#include "solver.hpp"

#include "chebyshev.hpp"
#include "schedule.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <chrono>
#include <optional>

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
  if (schedule != Schedule::insertion) {
    color_collisions(scratch.collisions, scratch.collision_coloring);
    if (!scratch.particle_contacts.empty()) {
      if (model.fixed.size() != std::size_t(model.num_particles())) model.fixed = pinned_flags(model.inverse_mass);
      color_particle_contacts(scratch.particle_contacts, model.fixed, scratch.contact_coloring);
    }
  }
  const bool accelerate = params.chebyshev.enabled && schedule != Schedule::insertion && params.iterations > 1;
  using Keep = typename PaddedPositions<Real>::Keep;
  Sweeper<Real> sweeper(model, state, scratch, schedule, update, reverse, parallel, config, params.jacobi_omega,
                        accelerate ? Keep::per_sweep : Keep::substep);
  sweeper.begin(time);
  Real* p = scratch.p.data();
  SolveReport report;
  if (!accelerate) {
    // One team for all the sweeps (team.hpp), each member with its own copy of the sweeper, unless the last teams
    // lacked their workers (retune_team).
    const bool team = sweeper.team_ready() && scratch.team_skip == 0;
    if (sweeper.team_ready() && !team) --scratch.team_skip;
    if (team) {
      const Sweeper<Real> proto = sweeper;
      const auto start = std::chrono::steady_clock::now();
      const int threads = tbb::this_task_arena::max_concurrency();
      const Team::Outcome outcome = Team::run(threads, scratch.team_wait, [&](Team::Member& member) {
        std::optional<Sweeper<Real>> own;  // member 0 sweeps with `sweeper` itself, so end() sees its state
        Sweeper<Real>& s = member.rank == 0 ? sweeper : own.emplace(proto);
        s.join(&member);
        for (int it = 0; it < params.iterations; ++it) s.sweep(p);
        s.join(nullptr);
      });
      retune_team(scratch, std::chrono::steady_clock::now() - start, outcome.members);
      report.threads = outcome.members;
      report.wait_fraction = outcome.wait_fraction;
    } else {
      for (int it = 0; it < params.iterations; ++it) sweeper.sweep(p);
    }
    sweeper.end(p);
    return report;
  }
  // ρ = 0: the ρ measured before (kept in the state, never in the user's parameters), or measure it now.
  Chebyshev<Real> settings = params.chebyshev;
  if (settings.rho == Real(0)) settings.rho = state.chebyshev_rho;
  ChebyshevAccelerator<Real> chebyshev(settings, params.iterations, model.num_particles(), state, scratch, parallel,
                                       config);
  for (int it = 0; it < params.iterations; ++it) {
    chebyshev.before(it, p);
    sweeper.sweep(p);
    chebyshev.after(it, p);
  }
  sweeper.end(p);
  report.chebyshev_fell_back = chebyshev.fell_back();
  if (chebyshev.estimate() > Real(0)) state.chebyshev_rho = chebyshev.estimate();
  return report;
}

template <class Real> void retune_team(Scratch<Real>& k, std::chrono::steady_clock::duration took, int members) {
  // The next team waits for its workers at most a tenth of this one's time (20 µs to 1 ms): on a large model a
  // worker that wakes late is worth waiting for, on a small one the wait would cost more than it brings. When no
  // worker joined (the arena's workers were asleep or busy), the next 2^m − 1 solves (m such misses in a row,
  // m ≤ 6) fork per loop instead, so a worker that never comes costs a wait only now and then.
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(took);
  k.team_wait = std::clamp(us / 10, std::chrono::microseconds(20), std::chrono::microseconds(1000));
  k.team_misses = members == 1 ? std::min(k.team_misses + 1, 6) : 0;
  k.team_skip = (1 << k.team_misses) - 1;
}

template void retune_team(Scratch<float>&, std::chrono::steady_clock::duration, int);
template void retune_team(Scratch<double>&, std::chrono::steady_clock::duration, int);
template SolveReport solve(Model<float>&, State<float>&, Scratch<float>&, const StepParams<float>&, const ParallelConfig&,
                    double, bool);
template SolveReport solve(Model<double>&, State<double>&, Scratch<double>&, const StepParams<double>&,
                    const ParallelConfig&, double, bool);

}  // namespace pbd::detail
