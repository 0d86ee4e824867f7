// A step's sub-steps (solver.hpp: run_substeps): one sub-step function, steps 1–5, written once over its runner.
//   ForkRunner  every step: the per-particle passes are parallel loops that fork and join (run_range), contacts are
//               generated, the solve is solve() (whose sweeps may hold a team of their own, solver.cpp)
//   TeamRunner  a step that is only predict, the hierarchy's pass, sweeps and update (step_on_team): one team of
//               threads (team.hpp) runs all of its sub-steps, each member calling the same sub-step function; the
//               particle passes and the hierarchy's loops are the team's loops (the particle passes over the same
//               parts of the particles the sweeps use), so a sub-step costs no fork/join and its particles stay in
//               their thread's cache. When the sweeps keep the positions padded and no hierarchy reads p,
//               prediction writes the padded copy and the update reads it.
// Both give the same bits: every pass gives the same bits however its loop is cut (tested).
#include "substep.hpp"

#include "pbd/detail/fault_injection.hpp"
#include "fibers.hpp"
#include "contact/particle_contacts.hpp"
#include "contact/prestabilize.hpp"
#include "contact/scratch.hpp"
#include "solve/hierarchy.hpp"
#include "solve/integrate.hpp"
#include "solve/restitution.hpp"
#include "solve/sweep.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>

namespace pbd::detail {
namespace {

using clock = std::chrono::steady_clock;
double seconds(clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// The schedule of a step on a team: blocks or colors (step_on_team admits no other solver).
template <class Real> Schedule team_schedule(const StepContext<Real>& c) {
  return uses_blocks(c.params.solver) ? Schedule::blocks : Schedule::colors;
}

// The runner of a step whose loops fork and join.
template <class Real> struct ForkRunner {
  static constexpr bool kTeam = false;
  StepContext<Real>& c;
  bool parallel;
  bool leader() const { return true; }
  // A per-particle pass (pass 0: prediction, 1: velocity update; each keeps its affinity partitioner).
  template <class Body> void particles(int pass, const Body& body) {
    run_range(0, c.model.num_particles(), parallel, c.config, c.scratch.particle_partitioners[pass], body);
  }
  // A loop over `n` chunks of `size` particles (pass 2: the free bodies' sums), with its own partitioner.
  template <class Body> void chunks(Index n, Index size, const Body& body) {
    run_range(0, n, parallel, per_block(c.config, std::size_t(size)), c.scratch.particle_partitioners[2], body);
  }
  // A loop of the hierarchy's pass (run_hierarchy), with its own partitioner.
  template <class Body> void loop(std::size_t id, Index b, Index e, const Body& body) {
    run_range(b, e, parallel, c.config, c.scratch.hierarchy.partitioners[id], body);
  }
};

// The runner of one member of the team that runs a whole step.
template <class Real> struct TeamRunner {
  static constexpr bool kTeam = true;
  StepContext<Real>& c;
  Team::Member& member;
  std::optional<Sweeper<Real>>& shared;  // this sub-step's sweeper, set up by member 0
  bool share;                            // the particle passes are shared (large enough)
  std::uint64_t ticks = 0, waited = 0;   // this member's ticks in the sweeps, and in their barriers
  bool leader() const { return member.rank == 0; }
  template <class Body> void particles(int, const Body& body) {
    member.loop(0, std::size_t(c.model.num_particles()), share,
                [&](std::size_t i, std::size_t j) { body(Index(i), Index(j)); });
  }
  // A loop of the hierarchy's pass, shared by the rule of the sweeps' team loops (Sweeper::team_loop_share_below).
  template <class Body> void loop(std::size_t, Index b, Index e, const Body& body) {
    const bool shared = std::size_t(e - b) >= Sweeper<Real>::team_loop_share_below(c.config, member.size());
    member.loop(std::size_t(b), std::size_t(e), shared, [&](std::size_t i, std::size_t j) { body(Index(i), Index(j)); });
  }
};

// The external forces of sub-step s at time t: the step's, plus the callback's (checked finite) when there is one.
template <class Real> const Real* substep_forces(StepContext<Real>& c, int s, double t) {
  if (!c.callback || !*c.callback) return c.forces;
  Scratch<Real>& k = c.scratch;
  const Index n = c.model.num_particles();
  k.callback_forces.setZero(3, n);
  (*c.callback)(t, c.state.x, k.callback_forces);
  for (Eigen::Index i = 0; i < k.callback_forces.cols(); ++i)
    if (!k.callback_forces.col(i).allFinite())
      throw Error(message("step: the force callback returned a non-finite force on particle ", i, " at sub-step ", s,
                          " (t = ", t, " s); the step was not taken"));
  if (c.forces) k.callback_forces += Eigen::Map<const Matrix3X<Real>>(c.forces, 3, n);
  return k.callback_forces.data();
}

// Step 3: collisions with the colliders and particle contacts (the velocities after forces are n·v before the
// solve: restitution). Both at once when both run in parallel: their outputs are apart, and the colliders' chunks
// fill the other threads while the broad phase runs its serial passes; not below the particles from which the broad
// phase forks (there waking a second thread costs more than it saves).
template <class Real> void generate_contacts(StepContext<Real>& c, bool parallel) {
  Model<Real>& m = c.model;
  State<Real>& st = c.state;
  Scratch<Real>& k = c.scratch;
  k.collisions.clear();
  k.particle_contacts.clear();
  if (!m.contact.empty()) cook_contact_bodies(m);
  if (!k.contact) k.contact = std::make_shared<ContactScratch<Real>>();
  const ParticleSurfaces<Real> surfaces = m.contact.empty() ? ParticleSurfaces<Real>{}
                                                            : ParticleSurfaces<Real>{m.contact.radius.data(), m.contact.material.data()};
  const Real margin = c.params.collision_margin;
  auto colliders = [&] {
    generate_collisions_chunked(m.colliders, st.x, k.p, st.v, m.inverse_mass, margin, surfaces, parallel,
                                k.contact->collision_chunks, k.collisions.items);
  };
  auto contacts = [&] { generate_particle_contacts(m, st.x, k.p, st.v, margin, parallel, k.contact->grid,
                                                    k.particle_contacts.items); };
  const bool with_colliders = !m.colliders.empty(), with_contacts = m.contact.particle_contacts();
  if (with_colliders && with_contacts && parallel && m.num_particles() >= kParallelContactsFrom) {
    tbb::parallel_invoke(colliders, contacts);
  } else {
    if (with_colliders) colliders();
    if (with_contacts) contacts();
  }
  // A particle that starts the sub-step behind a collider's surface leaves it with no gain in speed.
  if (with_colliders) prestabilize(k.collisions.items, k.particle_contacts.items, st.x, k.p, k.contact->moved,
                                   k.contact->moved_marks);
}

// Step 5's free bodies: each gives back the momentum and angular momentum the solve changed (free_bodies.hpp).
template <class Real> void despin(const FreeBodies<Real>& fb, const Real* p, Real* v, Index b, Index e) {
  for (Index i = b; i < e; ++i) {
    const Index body = fb.body[i];
    if (body == FreeBodies<Real>::kNone || std::isnan(fb.omega[9 * std::size_t(body)])) continue;
    const double* w = fb.omega.data() + 9 * std::size_t(body);
    const Eigen::Vector3d r = Eigen::Vector3d(double(p[3 * i]) - w[3], double(p[3 * i + 1]) - w[4], double(p[3 * i + 2]) - w[5]);
    const Eigen::Vector3d spin = Eigen::Vector3d(w[0], w[1], w[2]).cross(r);
    for (int d = 0; d < 3; ++d) v[3 * std::size_t(i) + d] -= Real(spin[d] + w[6 + d]);
  }
}

// Step 4 on a team member: this sub-step's sweeps on the member's own copy of the sweeper; returns whether the
// solved positions are in the padded copy.
template <class Real> bool sweep_on_team(TeamRunner<Real>& run, Sweeper<Real>& own, Real* q, Real* p) {
  const std::uint64_t t0 = Team::ticks(), w0 = run.member.waited;
  own.join(&run.member);
  if (q) own.adopt_padded();
  for (int it = 0; it < run.c.params.iterations; ++it) own.sweep(p);
  const bool in_q = own.padded();
  if (!in_q) own.end(p);
  own.join(nullptr);
  run.ticks += Team::ticks() - t0;
  run.waited += run.member.waited - w0;
  return in_q;
}

// One sub-step s (solver.hpp, steps 1–5) on `run`; x and p trade places at its end.
template <class Real, class Runner> void substep(StepContext<Real>& c, Runner& run, int s, SubstepsReport& out) {
  Model<Real>& m = c.model;
  State<Real>& st = c.state;
  Scratch<Real>& k = c.scratch;
  const Real h = c.h;
  const double t = st.time + double(h) * double(s + 1);
  // Symmetric order: odd sub-steps, numbered from the world's time, sweep backwards.
  const bool reverse = c.params.sweep_order == SweepOrder::symmetric && ((c.first_substep + s) & 1) != 0;
  const bool hierarchy = c.params.hierarchy.enabled && m.hierarchy;
  const auto t0 = clock::now();
  std::optional<Sweeper<Real>> own;
  Real* q = nullptr;
  if constexpr (Runner::kTeam) {
    // Member 0 sets up this sub-step's sweeper: every member copied the last one before the last sub-step's first
    // shared loop (a team forms only with one), whose barrier member 0 has passed, so no member still reads it.
    if (run.leader() && s > 0) {
      run.shared.emplace(m, st, k, team_schedule(c), Update::in_place, reverse, true, c.config);
      run.shared->begin(t);
    }
    run.member.wait();
    own.emplace(*run.shared);
    if (own->stays_padded() && !hierarchy) q = k.padded.data();  // the hierarchy's pass reads and writes p
  }
  const Real* f = Runner::kTeam ? c.forces : substep_forces(c, s, t);
  const auto t1 = clock::now();
  Real* x = st.x.data();
  Real* p = k.p.data();
  Real* v = st.v.data();
  const Real* w = m.inverse_mass.data();
  // 1.–2. forces, damping, predict (into the padded copy when the sweeps keep the positions there)
  run.particles(0, [&](Index b, Index e) {
    Predict<Real> predict(c.params, h, w, x, v, f, p);
    predict.q = q;
    predict(b, e);
  });
  const auto t2 = clock::now();
  // Fault points (tests: fault_injection.hpp) after each phase, only where the step's own thread runs the sub-step:
  // a team's members run it together, and its step's points follow the team (run_substeps).
  if constexpr (!Runner::kTeam) fault_point(FaultPhase::predict);
  // 3. contacts (a team's step has none)
  if constexpr (!Runner::kTeam) generate_contacts(c, run.parallel);
  if constexpr (!Runner::kTeam) fault_point(FaultPhase::contacts);
  const auto t3 = clock::now();
  // 4. solve: the hierarchy's coarse-to-fine pass (hierarchy.hpp) on the runner's loops, then the sweeps
  if (hierarchy) {
    run_hierarchy(*m.hierarchy, k.hierarchy, p, m.num_particles(), h,
                  [&](std::size_t id, Index b, Index e, const auto& body) { run.loop(id, b, e, body); });
    if (run.leader()) out.seconds_hierarchy += seconds(t3, clock::now());
  }
  bool in_q = false;
  if constexpr (Runner::kTeam) {
    in_q = sweep_on_team(run, *own, q, p);
  } else {
    const SolveReport solved = solve(m, st, k, c.params, c.config, t, reverse);
    out.chebyshev_fallbacks += solved.chebyshev_fell_back ? 1 : 0;
    out.seconds_waiting += solved.wait_fraction * seconds(t3, clock::now());
    out.threads = std::max(out.threads, solved.threads);
  }
  // 4b. the fibers' plastic flow at the solved positions (fibers.hpp; never on a team: step_on_team)
  if constexpr (!Runner::kTeam)
    if (c.flow) flow_fibers(m, p);
  if constexpr (!Runner::kTeam) fault_point(FaultPhase::solve);
  const auto t4 = clock::now();
  // 5. update (integrate.hpp), from the padded copy when the solved positions are there; free bodies get back the
  // momentum and angular momentum the solve changed (free_bodies.hpp); then restitution (Müller et al. 2006 §3.5):
  // the impacts of this sub-step leave at e × their approach speed.
  FreeBodies<Real>& fb = k.free_bodies;
  bool spin = false;
  if constexpr (!Runner::kTeam) {
    if (find_free_contacts<Real>(fb, k.collisions.items, k.particle_contacts.items)) {
      run.chunks(Index(fb.parts.size()), kSpinChunk, [&](Index b, Index e) {
        for (Index chunk = b; chunk < e; ++chunk) sum_free_chunk<Real>(m, fb, chunk, x, p, v, h);
      });
      spin = find_solver_spin(fb);
    }
  }
  run.particles(1, [&](Index b, Index e) {
    if (in_q) update_velocities_from_padded(h, x, k.padded.data(), p, v, b, e);
    else update_velocities(h, x, p, v, b, e);
    if (spin) despin(fb, p, v, b, e);
  });
  if constexpr (!Runner::kTeam)
    apply_restitution<Real>(k.collisions.items, k.collision_lambda, k.particle_contacts.items,
                            k.particle_contact_lambda, w, v, c.params.gravity.norm() * h);
  if constexpr (!Runner::kTeam) fault_point(FaultPhase::update);
  if (run.leader()) {
    st.x.swap(k.p);
    const auto t5 = clock::now();
    out.seconds_integrate += seconds(t1, t2) + seconds(t4, t5);
    out.seconds_collisions += seconds(t2, t3);
    out.seconds_solve += seconds(t3, t4) + (Runner::kTeam ? seconds(t0, t1) : 0.0);
  }
}

// The whole step on one team (step_on_team said yes, and `first` is its first sub-step's sweeper, begun).
template <class Real> void substeps_on_team(StepContext<Real>& c, std::optional<Sweeper<Real>>& first, SubstepsReport& out) {
  Scratch<Real>& k = c.scratch;
  const Index n = c.model.num_particles();
  std::atomic<std::uint64_t> sweep_ticks{0}, sweep_waited{0};
  const auto start = clock::now();
  const Team::Outcome outcome = Team::run(tbb::this_task_arena::max_concurrency(), k.team_wait, [&](Team::Member& member) {
    const bool share = n > 0 && std::size_t(n) >= Sweeper<Real>::team_loop_share_below(c.config, member.size());
    TeamRunner<Real> run{c, member, first, share};
    SubstepsReport mine;
    for (int s = 0; s < c.params.substeps; ++s) substep(c, run, s, mine);
    if (member.rank == 0) out = mine;
    sweep_ticks.fetch_add(run.ticks, std::memory_order_relaxed);
    sweep_waited.fetch_add(run.waited, std::memory_order_relaxed);
  });
  retune_team(k, clock::now() - start, outcome.members);
  out.threads = outcome.members;
  const std::uint64_t all = sweep_ticks.load();
  const double wait = outcome.members > 1 && all ? std::min(1.0, double(sweep_waited.load()) / double(all)) : 0.0;
  out.seconds_waiting = wait * out.seconds_solve;
}

}  // namespace

template <class Real> SubstepsReport run_substeps(StepContext<Real>& c) {
  SubstepsReport out;
  Scratch<Real>& k = c.scratch;
  k.p.resize(3, c.model.num_particles());
  // The one place a step's runner is chosen: one team for the whole step when the step is only predict, sweeps and
  // update, and the sweeps would form a team anyway (Sweeper::team_possible); otherwise sub-step by sub-step.
  if (c.params.hierarchy.enabled && c.model.hierarchy)
    prepare_hierarchy(*c.model.hierarchy, k.hierarchy, c.model.num_particles());
  std::optional<Sweeper<Real>> first;
  if (step_on_team(c)) {
    const Schedule schedule = team_schedule(c);
    const bool reverse = c.params.sweep_order == SweepOrder::symmetric && (c.first_substep & 1) != 0;
    first.emplace(c.model, c.state, k, schedule, Update::in_place, reverse, true, c.config);
    if (!first->team_possible()) first.reset();  // decided before begin(), which resets λ: nothing changed
  }
  if (first) {
    k.collisions.clear();
    first->begin(c.state.time + double(c.h));
    substeps_on_team(c, first, out);
    out.on_team = true;
    for (const FaultPhase phase : {FaultPhase::predict, FaultPhase::solve, FaultPhase::update}) fault_point(phase);
    return out;
  }
  ForkRunner<Real> run{c, is_parallel(c.params.solver)};
  for (int s = 0; s < c.params.substeps; ++s) substep(c, run, s, out);
  return out;
}

template <class Real> bool step_on_team(const StepContext<Real>& c) {
  const Model<Real>& m = c.model;
  const Solver solver = c.params.solver;
  return is_parallel(solver) && solver != Solver::jacobi && !(c.callback && *c.callback) && m.colliders.empty() &&
         m.contact.empty() && m.user.empty() && m.volume.table.empty() && c.scratch.free_bodies.count == 0 &&
         tbb::this_task_arena::max_concurrency() >= 2 && c.scratch.team_skip == 0 &&
         !(c.params.chebyshev.enabled && c.params.iterations > 1) && !c.flow;
}

#define PBD_SUBSTEP_INSTANTIATE(Real)                                                              \
  template SubstepsReport run_substeps(StepContext<Real>&);                                        \
  template bool step_on_team(const StepContext<Real>&);

PBD_SUBSTEP_INSTANTIATE(float)
PBD_SUBSTEP_INSTANTIATE(double)
#undef PBD_SUBSTEP_INSTANTIATE

}  // namespace pbd::detail
