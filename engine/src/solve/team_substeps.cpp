// All of a step's sub-steps on one team of threads (solver.hpp: run_substeps_on_team).
#include "integrate.hpp"
#include "solver.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>

namespace pbd::detail {

template <class Real>
TeamSubstepsReport run_substeps_on_team(Model<Real>& m, State<Real>& state, Scratch<Real>& k,
                                        const StepParams<Real>& params, const ParallelConfig& config,
                                        const Real* forces, bool has_callback) {
  TeamSubstepsReport report;
  const Solver solver = params.solver;
  const int threads = tbb::this_task_arena::max_concurrency();
  if (!is_parallel(solver) || solver == Solver::jacobi || has_callback || !m.colliders.empty() || !m.contact.empty() ||
      !m.user.empty() || !m.volume.table.empty() || k.free_bodies.count != 0 || threads < 2 || k.team_skip != 0 ||
      (params.chebyshev.enabled && params.iterations > 1))
    return report;
  const Schedule schedule = uses_blocks(solver) ? Schedule::blocks : Schedule::colors;
  const int substeps = params.substeps;
  const Real h = params.dt / Real(substeps);
  const long long first = std::llround(state.time / double(params.dt)) * substeps;
  auto time_of = [&](int s) { return state.time + double(h) * double(s + 1); };
  auto reverse_of = [&](int s) { return params.sweep_order == SweepOrder::symmetric && ((first + s) & 1) != 0; };
  std::optional<Sweeper<Real>> shared;  // this sub-step's sweeper, set up by member 0 (begin())
  shared.emplace(m, state, k, schedule, Update::in_place, reverse_of(0), true, config);
  if (!shared->team_possible()) return report;  // decided before begin(), which resets λ: nothing changed
  k.collisions.clear();
  shared->begin(time_of(0));

  const Index n = m.num_particles();
  k.p.resize(3, n);
  Real* positions[2] = {state.x.data(), k.p.data()};  // sub-step s: x = positions[s & 1], p the other
  Real* v = state.v.data();
  const Real* w = m.inverse_mass.data();
  using clock = std::chrono::steady_clock;
  double integrate = 0.0, solve = 0.0;
  std::atomic<std::uint64_t> sweep_ticks{0}, sweep_waited{0};
  const auto start = clock::now();
  const Team::Outcome outcome = Team::run(threads, k.team_wait, [&](Team::Member& member) {
    const bool share = n > 0 && std::size_t(n) >= Sweeper<Real>::team_loop_share_below(config, member.size());
    std::uint64_t ticks = 0, waited = 0;
    for (int s = 0; s < substeps; ++s) {
      const Real* x = positions[s & 1];
      Real* p = positions[(s + 1) & 1];
      const auto a = clock::now();
      // Member 0 sets up this sub-step's sweeper: every member copied the last one before the last sub-step's first
      // shared loop (a team forms only with one), whose barrier member 0 has passed, so no member still reads it.
      if (member.rank == 0 && s > 0) {
        shared.emplace(m, state, k, schedule, Update::in_place, reverse_of(s), true, config);
        shared->begin(time_of(s));
      }
      member.wait();
      Sweeper<Real> own = *shared;
      // When the sweeps keep the positions padded, predict writes the padded copy and the update reads it: no pass
      // pads or unpads them, and each member touches its own particles only.
      Real* q = own.stays_padded() ? k.padded.data() : nullptr;
      const auto b = clock::now();
      // 1.–2. forces, damping, predict: the team's parts of the particles
      member.loop(0, std::size_t(n), share, [&](std::size_t i, std::size_t j) {
        Predict<Real> predict(params, h, w, x, v, forces, p);
        predict.q = q;
        predict(Index(i), Index(j));
      });
      const auto c = clock::now();
      // 4. the sweeps
      const std::uint64_t t0 = Team::ticks(), w0 = member.waited;
      own.join(&member);
      if (q) own.adopt_padded();
      for (int it = 0; it < params.iterations; ++it) own.sweep(p);
      const bool in_q = own.padded();
      if (!in_q) own.end(p);
      own.join(nullptr);
      ticks += Team::ticks() - t0;
      waited += member.waited - w0;
      const auto d = clock::now();
      // 5. update (no free body: nothing else), from the padded copy when the solved positions are there
      member.loop(0, std::size_t(n), share, [&](std::size_t i, std::size_t j) {
        if (in_q) update_velocities_from_padded(h, x, k.padded.data(), p, v, Index(i), Index(j));
        else update_velocities(h, x, p, v, Index(i), Index(j));
      });
      if (member.rank == 0) {
        const auto e = clock::now();
        using seconds = std::chrono::duration<double>;
        integrate += seconds(c - b).count() + seconds(e - d).count();
        solve += seconds(b - a).count() + seconds(d - c).count();
      }
    }
    sweep_ticks.fetch_add(ticks, std::memory_order_relaxed);
    sweep_waited.fetch_add(waited, std::memory_order_relaxed);
  });
  if (substeps & 1) state.x.swap(k.p);  // x = p after each sub-step: an odd count ends in k.p
  const auto took = std::chrono::duration_cast<std::chrono::microseconds>(clock::now() - start);
  k.team_wait = std::clamp(took / 10, std::chrono::microseconds(20), std::chrono::microseconds(1000));
  k.team_misses = outcome.members == 1 ? std::min(k.team_misses + 1, 6) : 0;
  k.team_skip = (1 << k.team_misses) - 1;
  report.ran = true;
  report.threads = outcome.members;
  report.seconds_integrate = integrate;
  report.seconds_solve = solve;
  const std::uint64_t all = sweep_ticks.load();
  report.wait_fraction = outcome.members > 1 && all ? std::min(1.0, double(sweep_waited.load()) / double(all)) : 0.0;
  return report;
}

template TeamSubstepsReport run_substeps_on_team(Model<float>&, State<float>&, Scratch<float>&,
                                                 const StepParams<float>&, const ParallelConfig&, const float*, bool);
template TeamSubstepsReport run_substeps_on_team(Model<double>&, State<double>&, Scratch<double>&,
                                                 const StepParams<double>&, const ParallelConfig&, const double*, bool);

}  // namespace pbd::detail
