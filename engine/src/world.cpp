// World: the step (forces, predict, collisions, solve, update), its statistics, and the world's life cycle.
// Adding, removing and validating constraints and particles: edit.cpp.
#include "pbd/world.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/metrics.hpp"
#include "solve/hierarchy.hpp"
#include "solve/schedule.hpp"
#include "solve/solver.hpp"
#include "pbd/detail/fault_injection.hpp"
#include "fibers.hpp"
#include "step_undo.hpp"
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

// The first particle whose position or velocity in s is not finite: (index, "position" or "velocity"), or (-1, "").
template <class Real> std::pair<Index, const char*> first_non_finite(const detail::State<Real>& s) {
  if (s.x.allFinite() && s.v.allFinite()) return {Index(-1), ""};
  for (Index i = 0; i < Index(s.x.cols()); ++i) {
    if (!s.x.col(i).allFinite()) return {i, "position"};
    if (!s.v.col(i).allFinite()) return {i, "velocity"};
  }
  return {Index(-1), ""};
}

template <class Real> std::string non_finite_value(const detail::State<Real>& s, Index i, const char* what) {
  const auto c = (what[0] == 'p' ? s.x : s.v).col(i);
  return detail::message("(", c[0], ", ", c[1], ", ", c[2], ")");
}

}  // namespace

template <class Real> void World<Real>::check_state_finite() const {
  const auto [i, what] = first_non_finite(state_);
  if (i == Index(-1)) return;
  throw Error(detail::message("step: particle ", i, " has a non-finite ", what, " ", non_finite_value(state_, i, what),
                              ", written between steps"));
}

// A step that made some position or velocity non-finite (in-range inputs that blow up: a huge velocity, gravity,
// compliance) fails there, naming the first such particle, and is undone: nothing keeps or writes a non-finite state.
template <class Real> void World<Real>::check_stepped_state(long long step) const {
  const auto [i, what] = first_non_finite(state_);
  if (i == Index(-1)) return;
  throw Error(detail::message("step ", step, " (t = ", state_.time + double(params_.dt), " s): particle ", i,
                              " got a non-finite ", what, " ", non_finite_value(state_, i, what),
                              "; the step was undone"));
}

// A closed mesh whose volume a step took below −0.1% of its target (the sign is the mesh's orientation, the margin
// keeps a mesh squashed flat at the start, at 0 within rounding, stepping) has turned inside out: a pressure jump
// larger than the mesh can follow. The volume constraint would push it further out of shape, so the step fails,
// naming the constraint, and is undone (docs/robustness.md).
template <class Real> void World<Real>::check_volumes_not_inverted(long long step) const {
  const VolumeConstraints<Real>& volumes = model_.volume.table;
  const double t = state_.time + double(params_.dt);
  for (std::size_t i = 0; i < volumes.items.size(); ++i) {
    const VolumeConstraint<Real>& c = volumes.items[i];
    const std::span<const std::array<Index, 3>> tris(volumes.triangles.data() + c.triangle_begin,
                                                     std::size_t(c.triangle_end - c.triangle_begin));
    const double six = double(six_volume<Real>(tris, state_.x)), target = c.pressure.at(t) * double(c.rest);
    if (six < -1e-3 * target)
      throw Error(detail::message("step ", step, " (t = ", t, " s): volume constraint ", i, " turned its mesh inside ",
                                  "out (volume ", six / 6, " m^3, target ", target / 6, " m^3): its pressure changed ",
                                  "faster than the mesh can follow; ramp it (a pressure duration) or give the surface ",
                                  "stretch; the step was undone"));
  }
}

// A step's caches, cooked from the model before anything changes (a failure here changes no state): the sub-step
// coefficients, the colors or blocks, the hierarchy.
template <class Real> void World<Real>::cook_for_step(detail::Scratch<Real>& k) {
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
}

template <class Real> void World<Real>::advance(const Real* forces) {
  if (host_wrote_) {  // the host held a mutable map: check what it may have written, before anything changes
    check_state_finite();
    host_wrote_ = false;
  }
  const auto t0 = clock::now();
  detail::Scratch<Real>& k = scratch();
  // Whatever fails below (the host's callback, an allocation, a non-finite state, a break's edit), the world is put
  // back as it was: step_undo.hpp.
  const StepStats stats_before = stats_;
  const std::vector<FiberBreak> breaks_before = breaks_;
  const std::vector<TornParticle> copies_before = copies_;
  stats_ = StepStats{};
  cook_for_step(k);
  detail::StepUndo<Real> undo(model_, state_, k.before);
  Real* const x_storage = state_.x.data();
  try {
    take_step(k, forces, undo);
  } catch (...) {
    // Each sub-step swaps x with the predicted positions k.p: a failure at an odd one leaves x in k.p's storage.
    if (state_.x.data() != x_storage) state_.x.swap(k.p);
    undo.restore(model_, state_);
    stats_ = stats_before;
    breaks_ = breaks_before;
    copies_ = copies_before;
    throw;
  }
  stats_.seconds = seconds_since(t0);
}

template <class Real>
void World<Real>::take_step(detail::Scratch<Real>& k, const Real* forces, detail::StepUndo<Real>& undo) {
  follow_pins(model_.template store<TetherConstraint<Real>>().items, state_.x, model_.inverse_mass);
  const Real h = params_.dt / Real(params_.substeps);
  // Each sub-step swaps x with the predicted positions k.p, so an odd count would leave x in the other buffer: put
  // the result back into x's own storage (one copy) so that maps of positions() stay valid across steps.
  Real* const x_storage = state_.x.data();
  detail::update_free_bodies(model_, k.free_bodies);
  // The sub-steps (solver.hpp: run_substeps), on the runner it chooses.
  const long long step = std::llround(state_.time / double(params_.dt));
  detail::StepContext<Real> context{model_, state_, k, params_, parallel_, forces, &force_callback_, h,
                                    step * params_.substeps};
  context.flow = detail::fibers_flow(model_);
  const detail::SubstepsReport run = detail::run_substeps(context);
  if (state_.x.data() != x_storage) {
    state_.x.swap(k.p);
    state_.x = k.p;  // same size: copied into x_storage, no allocation
  }
  check_stepped_state(step + 1);  // before anything reads or keeps a non-finite state
  check_volumes_not_inverted(step + 1);
  stats_.seconds_integrate = run.seconds_integrate;
  stats_.seconds_collisions = run.seconds_collisions;
  stats_.seconds_solve = run.seconds_solve;
  stats_.seconds_waiting = run.seconds_waiting;
  stats_.seconds_hierarchy = run.seconds_hierarchy;
  stats_.solve_threads = run.threads;
  stats_.chebyshev_fallbacks = run.chebyshev_fallbacks;
  state_.time += double(params_.dt);
  state_.lambda_h2 = double(h) * double(h);
  break_fibers(undo);
  stats_.substeps = params_.substeps;
  stats_.sweeps = params_.substeps * params_.iterations;
  stats_.collisions = k.collisions.size() + k.particle_contacts.size();
  const Real rho = params_.chebyshev.rho != Real(0) ? params_.chebyshev.rho : state_.chebyshev_rho;  // given or measured
  stats_.chebyshev_rho = params_.chebyshev.enabled ? double(rho) : 0.0;
  if (measure_violation_) stats_.violation = constraint_violations(*this);
  detail::fault_point(detail::FaultPhase::step_end);
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
