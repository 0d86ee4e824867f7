// World: the step (forces, predict, collisions, solve, update), its statistics, and the world's life cycle.
// Adding, removing and validating constraints and particles: edit.cpp.
#include "pbd/world.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/metrics.hpp"
#include "solve/hierarchy.hpp"
#include "solve/schedule.hpp"
#include "solve/solver.hpp"
#include "fibers.hpp"
#include "substep.hpp"

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
    : model_(o.model_), state_(o.state_), params_(o.params_), stats_(o.stats_), breaks_(o.breaks_),
      copies_(o.copies_), measure_violation_(o.measure_violation_), host_wrote_(o.host_wrote_), parallel_(o.parallel_),
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

// Tethers follow their pins (tether.hpp): each target whose pin is pinned becomes that pin's position, read between
// steps, when nothing else runs; an unmoved pin writes the target's own value back, so the bits stay as they were.
template <class Real>
void follow_pins(std::vector<TetherConstraint<Real>>& tethers, const Matrix3X<Real>& x, const VectorX<Real>& w) {
  for (TetherConstraint<Real>& t : tethers)
    if (t.pin < Index(w.size()) && w[t.pin] == Real(0)) t.target = x.col(t.pin);  // kNoPin is out of range
}

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
  follow_pins(model_.template store<TetherConstraint<Real>>().items, state_.x, model_.inverse_mass);
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
  if (params_.hierarchy.enabled) detail::ensure_hierarchy(model_, params_.hierarchy);  // cooked once per edit
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
  detail::update_free_bodies(model_, k.free_bodies);
  // The sub-steps (solver.hpp: run_substeps), on the runner it chooses.
  const long long first_substep = std::llround(state_.time / double(params_.dt)) * params_.substeps;
  detail::StepContext<Real> context{model_, state_, k, params_, parallel_, forces, &force_callback_, h, first_substep};
  context.flow = detail::fibers_flow(model_);
  // Plastic flow changes the plastic strains during the sub-steps: kept too, when a later sub-step may fail.
  detail::PlasticRollback<Real> rollback_plastic(model_, rollback && context.flow);
  detail::SubstepsReport run;
  try {
    run = detail::run_substeps(context);
  } catch (...) {
    if (rollback) {
      state_.x = k.rollback_x;  // copied back, not swapped: maps the host holds on positions() stay valid
      state_.v = k.rollback_v;
      rollback_plastic.restore(model_);
    }
    keep_storage();
    throw;
  }
  stats_.seconds_integrate = run.seconds_integrate;
  stats_.seconds_collisions = run.seconds_collisions;
  stats_.seconds_solve = run.seconds_solve;
  stats_.seconds_waiting = run.seconds_waiting;
  stats_.seconds_hierarchy = run.seconds_hierarchy;
  stats_.solve_threads = run.threads;
  stats_.chebyshev_fallbacks = run.chebyshev_fallbacks;
  keep_storage();
  state_.time += double(params_.dt);
  state_.lambda_h2 = double(h) * double(h);
  break_fibers();
  stats_.substeps = params_.substeps;
  stats_.sweeps = params_.substeps * params_.iterations;
  stats_.collisions = k.collisions.size() + k.particle_contacts.size();
  const Real rho = params_.chebyshev.rho != Real(0) ? params_.chebyshev.rho : state_.chebyshev_rho;  // given or measured
  stats_.chebyshev_rho = params_.chebyshev.enabled ? double(rho) : 0.0;
  if (measure_violation_) stats_.violation = constraint_violations(*this);
  stats_.seconds = seconds_since(t0);
}

template <class Real> template <class C> std::vector<FiberReading> World<Real>::material_readings() const {
  static_assert(takes_material<C>(), "material_readings: a type that takes a stress-strain curve");
  return detail::read_fibers<C>(model_, state_);
}
template std::vector<FiberReading> World<float>::material_readings<FiberConstraint<float>>() const;
template std::vector<FiberReading> World<float>::material_readings<TetFiberConstraint<float>>() const;
template std::vector<FiberReading> World<double>::material_readings<FiberConstraint<double>>() const;
template std::vector<FiberReading> World<double>::material_readings<TetFiberConstraint<double>>() const;

template class World<float>;
template class World<double>;


}  // namespace pbd
