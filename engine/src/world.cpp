// World: the step (forces, predict, collisions, solve, update), its statistics, and the world's life cycle.
// Adding, removing and validating constraints and particles: edit.cpp.
#include "pbd/world.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/metrics.hpp"
#include "contact/particle_contacts.hpp"
#include "solve/integrate.hpp"
#include "solve/restitution.hpp"
#include "solve/parallel_range.hpp"
#include "solve/schedule.hpp"
#include "solve/solver.hpp"

#include <oneapi/tbb/parallel_invoke.h>

#include <chrono>
#include <type_traits>
#include <cmath>

namespace pbd {

namespace detail {
template <class Real> void ScratchDeleter<Real>::operator()(Scratch<Real>* s) const { delete s; }
template struct ScratchDeleter<float>;
template struct ScratchDeleter<double>;
}  // namespace detail

template <class Real> World<Real>::World() = default;
template <class Real> World<Real>::~World() = default;
template <class Real> World<Real>::World(World&&) noexcept = default;
template <class Real> World<Real>& World<Real>::operator=(World&&) noexcept = default;
template <class Real>
World<Real>::World(const World& o)
    : model_(o.model_), state_(o.state_), params_(o.params_), stats_(o.stats_),
      measure_violation_(o.measure_violation_), host_wrote_(o.host_wrote_), parallel_(o.parallel_),
      force_callback_(o.force_callback_) {}
template <class Real> World<Real>& World<Real>::operator=(const World& o) {
  if (this != &o) {
    World copy(o);
    *this = std::move(copy);
  }
  return *this;
}

template <class Real> detail::Scratch<Real>& World<Real>::scratch() {
  if (!scratch_) scratch_.reset(new detail::Scratch<Real>());
  return *scratch_;
}

template <class Real> std::span<const CollisionConstraint<Real>> World<Real>::last_collisions() const {
  if (!scratch_) return {};
  return scratch_->collisions.items;
}

template <class Real> std::span<const ParticleContact<Real>> World<Real>::last_particle_contacts() const {
  if (!scratch_) return {};
  return scratch_->particle_contacts.items;
}

template <class Real> void World<Real>::step() { advance(nullptr); }

template <class Real> void World<Real>::step(Eigen::Ref<const Positions> forces) {
  const Eigen::Index n = state_.x.cols();
  if (forces.rows() != 3 || forces.cols() != n)
    throw Error(detail::message("step: forces must be 3 x ", n, ", got ", forces.rows(), " x ", forces.cols()));
  for (Eigen::Index i = 0; i < forces.cols(); ++i)
    if (!forces.col(i).allFinite()) throw Error(detail::message("step: force on particle ", i, " is not finite"));
  if (forces.outerStride() == 3) return advance(forces.data());
  const Positions copy = forces;  // a strided view: make it contiguous once
  advance(copy.data());
}

template <class Real> void World<Real>::ensure_colored() {
  detail::update_colors(model_, uses_blocks(params_.solver) ? detail::Layout::blocks : detail::Layout::colors);
}

template <class Real> Index World<Real>::num_colors() {
  ensure_colored();
  Index n = model_.volume.num_colors();
  detail::for_each_type(model_, [&](const detail::TypeStore<Real>& type, std::size_t) { n += type.num_colors(); });
  return n;
}

namespace {

using clock = std::chrono::steady_clock;
double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }

}  // namespace

template <class Real> void World<Real>::check_state_finite() const {
  if (state_.x.allFinite() && state_.v.allFinite()) return;
  for (Index i = 0; i < num_particles(); ++i)
    for (const auto* what : {&state_.x, &state_.v})
      if (!what->col(i).allFinite()) {
        const auto c = what->col(i);
        throw Error(detail::message("step: particle ", i, " has a non-finite ", what == &state_.x ? "position" : "velocity",
                                    " (", c[0], ", ", c[1], ", ", c[2], "), written between steps"));
      }
}

template <class Real> void World<Real>::advance(const Real* forces) {
  if (host_wrote_) {  // the host held a mutable map: check what it may have written, before anything changes
    check_state_finite();
    host_wrote_ = false;
  }
  const auto t0 = clock::now();
  stats_ = StepStats{};
  detail::Scratch<Real>& k = scratch();
  const Real h = params_.dt / Real(params_.substeps);
  k.coeff.resize(model_.sets.size());
  for (std::size_t s = 0; s < k.coeff.size(); ++s)
    k.coeff[s] = coefficients<Real>(model_.sets[s], double(h), params_.iterations);
  if (params_.solver != Solver::serial) {
    const auto c0 = clock::now();
    ensure_colored();
    stats_.seconds_coloring = seconds_since(c0);
    stats_.colors = num_colors();
  }
  // A force callback may fail at a later sub-step: keep the state it started from so nothing is half-stepped.
  const bool rollback = force_callback_ && params_.substeps > 1;
  if (rollback) {
    k.rollback_x = state_.x;
    k.rollback_v = state_.v;
  }
  // Each sub-step swaps x with the predicted positions k.p, so an odd count would leave x in the other buffer: put
  // the result back into x's own storage (one copy) so that maps of positions() stay valid across steps.
  Real* const x_storage = state_.x.data();
  auto keep_storage = [&] {
    if (state_.x.data() == x_storage) return;
    state_.x.swap(k.p);
    state_.x = k.p;  // same size: copied into x_storage, no allocation
  };
  const bool parallel = is_parallel(params_.solver);
  const Index n = num_particles();
  detail::update_free_bodies(model_, k.free_bodies);
  // The whole step on one team of threads when it is only predict, sweeps and update (solver.hpp).
  const detail::TeamSubstepsReport team =
      detail::run_substeps_on_team(model_, state_, k, params_, parallel_, forces, bool(force_callback_));
  if (team.ran) {
    stats_.seconds_integrate = team.seconds_integrate;
    stats_.seconds_solve = team.seconds_solve;
    stats_.seconds_waiting = team.wait_fraction * team.seconds_solve;
    stats_.solve_threads = team.threads;
  }
  try {
    for (int s = 0; s < (team.ran ? 0 : params_.substeps); ++s) {
      const double t = state_.time + double(h) * double(s + 1);
      const Real* f = forces;
      if (force_callback_) {
        k.callback_forces.setZero(3, n);
        force_callback_(t, state_.x, k.callback_forces);
        for (Eigen::Index i = 0; i < k.callback_forces.cols(); ++i)
          if (!k.callback_forces.col(i).allFinite())
            throw Error(detail::message("step: the force callback returned a non-finite force on particle ", i,
                                        " at sub-step ", s, " (t = ", t, " s); the step was not taken"));
        if (forces) k.callback_forces += Eigen::Map<const Positions>(forces, 3, n);
        f = k.callback_forces.data();
      }
      // 1.–2. forces, damping, predict
      const auto t1 = clock::now();
      k.p.resize(3, n);
      detail::run_range(0, n, parallel, parallel_, k.particle_partitioners[0],
                        detail::Predict<Real>(params_, h, model_.inverse_mass.data(), state_.x.data(),
                                              state_.v.data(), f, k.p.data()));
      const auto t2 = clock::now();
      // 3. collisions and particle contacts (the velocities after forces are n·v before the solve: restitution)
      k.collisions.clear();
      k.particle_contacts.clear();
      if (!model_.contact.empty()) detail::cook_contact_bodies(model_);
      const ParticleSurfaces<Real> surfaces =
          model_.contact.empty() ? ParticleSurfaces<Real>{}
                                 : ParticleSurfaces<Real>{model_.contact.radius.data(), model_.contact.material.data()};
      auto colliders = [&] {
        detail::generate_collisions_chunked(model_.colliders, state_.x, k.p, state_.v, model_.inverse_mass,
                                            params_.collision_margin, surfaces, parallel, k.collision_chunks,
                                            k.collisions.items);
      };
      auto contacts = [&] {
        detail::generate_particle_contacts(model_, state_.x, k.p, state_.v, params_.collision_margin, parallel, k.grid,
                                           k.particle_contacts.items);
      };
      // Both at once when both run in parallel: their outputs are apart, and the colliders' chunks fill the other
      // threads while the broad phase runs its serial passes. Not below the particles from which the broad phase
      // forks: there the two take tens of microseconds, and waking a second thread costs more than it saves.
      const bool with_colliders = !model_.colliders.empty(), with_contacts = model_.contact.particle_contacts();
      if (with_colliders && with_contacts && parallel && n >= detail::kParallelContactsFrom) tbb::parallel_invoke(colliders, contacts);
      else {
        if (with_colliders) colliders();
        if (with_contacts) contacts();
      }
      const auto t3 = clock::now();
      // 4. solve (symmetric order: odd sub-steps, numbered from the world's time, sweep backwards)
      const long long substep = std::llround(state_.time / double(params_.dt)) * params_.substeps + s;
      const bool reverse = params_.sweep_order == SweepOrder::symmetric && (substep & 1) != 0;
      const detail::SolveReport solved = detail::solve(model_, state_, k, params_, parallel_, t, reverse);
      stats_.chebyshev_fallbacks += solved.chebyshev_fell_back ? 1 : 0;
      if (solved.chebyshev_estimate > 0.0) params_.chebyshev.rho = Real(solved.chebyshev_estimate);  // chebyshev.hpp
      const auto t4 = clock::now();
      // 5. update (integrate.hpp); free bodies get back the momentum and angular momentum the solve changed
      // (free_bodies.hpp).
      Real* v = state_.v.data();
      const Real* x = state_.x.data();
      const Real* p = k.p.data();
      detail::FreeBodies<Real>& fb = k.free_bodies;
      const bool despin =
          detail::measure_solver_spin<Real>(model_, fb, k.collisions.items, k.particle_contacts.items, x, p, v, h);
      detail::run_range(0, n, parallel, parallel_, k.particle_partitioners[1], [&](Index b, Index e) {
        detail::update_velocities(h, x, p, v, b, e);
        if (!despin) return;
        for (Index i = b; i < e; ++i) {
          const Index body = fb.body[i];
          if (body == detail::FreeBodies<Real>::kNone || std::isnan(fb.omega[9 * std::size_t(body)])) continue;
          const double* w = fb.omega.data() + 9 * std::size_t(body);
          const Eigen::Vector3d r = Eigen::Vector3d(double(p[3 * i]) - w[3], double(p[3 * i + 1]) - w[4], double(p[3 * i + 2]) - w[5]);
          const Eigen::Vector3d spin = Eigen::Vector3d(w[0], w[1], w[2]).cross(r);
          for (int d = 0; d < 3; ++d) v[3 * std::size_t(i) + d] -= Real(spin[d] + w[6 + d]);
        }
      });
      // Restitution (Müller et al. 2006 §3.5): the impacts of this sub-step leave at e × their approach speed.
      detail::apply_restitution<Real>(k.collisions.items, k.collision_lambda, k.particle_contacts.items,
                                k.particle_contact_lambda, model_.inverse_mass.data(), v, params_.gravity.norm() * h);
      state_.x.swap(k.p);
      using seconds = std::chrono::duration<double>;
      stats_.seconds_integrate += seconds(t2 - t1).count() + seconds_since(t4);
      stats_.seconds_collisions += seconds(t3 - t2).count();
      stats_.seconds_solve += seconds(t4 - t3).count();
      stats_.seconds_waiting += solved.wait_fraction * seconds(t4 - t3).count();
      stats_.solve_threads = std::max(stats_.solve_threads, solved.threads);
    }
  } catch (...) {
    if (rollback) {
      state_.x = k.rollback_x;  // copied back, not swapped: maps the host holds on positions() stay valid
      state_.v = k.rollback_v;
    }
    keep_storage();
    throw;
  }
  keep_storage();
  state_.time += double(params_.dt);
  stats_.substeps = params_.substeps;
  stats_.sweeps = params_.substeps * params_.iterations;
  stats_.collisions = k.collisions.size() + k.particle_contacts.size();
  stats_.chebyshev_rho = params_.chebyshev.enabled ? double(params_.chebyshev.rho) : 0.0;
  if (measure_violation_) stats_.violation = constraint_violations(*this);
  stats_.seconds = seconds_since(t0);
}

template class World<float>;
template class World<double>;


}  // namespace pbd
