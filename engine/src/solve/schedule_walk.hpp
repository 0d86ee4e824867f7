#pragma once
// The schedule walker (private): in which order a sweep visits one constraint type's constraints, and in which
// loops (sweep_loops.hpp). The schedules:
//   insertion  every constraint in the order the user added it (the serial reference), one call for the type
//   colors     color after color; within a color no two constraints write the same movable particle, so a color's
//              constraints run in parallel or one after the other with the same bits
//   blocks     the blocks' interiors first, for every type at once (interiors(): one parallel loop over the blocks,
//              a task projecting its blocks' constraints of every type, in types' order, each in insertion order
//              or, for a type with colored interiors (traits.hpp), run (color) after run; no
//              two blocks share a movable particle, so any number of threads gives the same bits); then each type's
//              boundary colors as under colors (block_layout.hpp)
//   reverse    (SweepOrder::symmetric, odd sub-steps) each type backwards: the colors in reverse order (a color's
//              constraints share no particle, so their own order never matters), each interior backwards
// What a range's constraints are projected with (the generic projection under an update rule, or a SIMD kernel on
// padded positions) is the caller's (sweep.hpp); the walker only cuts and orders.
#include "kernel_table.hpp"
#include "sweep_loops.hpp"

namespace pbd::detail {

enum class Schedule { insertion, colors, blocks };  // which order a sweep visits the constraints in

template <class Real> class ScheduleWalk {
public:
  ScheduleWalk(const Model<Real>& model, Schedule schedule, bool reverse)
      : m_(model), schedule_(schedule), reverse_(reverse) {}

  Schedule schedule() const { return schedule_; }
  bool reverse() const { return reverse_; }

  /// Calls body(c, b, e) for stored ranges [b, e) of each color c of `type` (the one at position t) a sweep visits after the
  /// interiors, color after color (backwards when reversed); ranges of a color are cut at multiples of `block` from
  /// its start (block > 1: a SIMD kernel's width; under the block schedule, the boundary's own cutting instead).
  template <class Body>
  void colors(SweepLoops<Real>& loops, const TypeStore<Real>& type, std::size_t t, Index block, const Body& body) const {
    const std::span<const Index> groups = type.groups();
    const Index all = groups.empty() ? 0 : Index(groups.size() - 1), first = type.num_blocks(), colors = all - first;
    const std::size_t base = loops.slots(std::size_t(colors));
    const Index* cuts = loops.team() ? cuts_of(t, all) : nullptr;  // only a team cuts at them
    for (Index j = 0; j < colors; ++j) {
      const Index c = first + (reverse_ ? colors - 1 - j : j);
      const std::size_t slot = base + std::size_t(c - first);
      const Index* color_cuts = cuts ? cuts + std::size_t(c) * (kCutParts + 1) : nullptr;
      auto range = [&](Index b, Index e) { body(c, b, e); };
      if (schedule_ == Schedule::colors && block > 1)
        loops.blocks_range(groups[c], groups[c + 1], block, loops.config(), slot, range, color_cuts);
      else loops.color(type, groups[c], groups[c + 1], color_cuts, slot, range);
    }
  }

  /// The particle cuts (Model::particle_cuts) of the type at position t with `colors` groups, when laid out in
  /// colors; else nullptr.
  const Index* cuts_of(std::size_t t, Index colors) const {
    if (t >= m_.particle_cuts.size()) return nullptr;
    const auto& cuts = m_.particle_cuts[t];
    if (cuts.size() != std::size_t(colors) * (kCutParts + 1)) return nullptr;
    return cuts.data();
  }

  /// The blocks' interiors (block schedule), task(first, last) per task of blocks [first, last).
  template <class Task> void interiors(SweepLoops<Real>& loops, const Task& task) const { loops.interiors(task); }

private:
  const Model<Real>& m_;
  Schedule schedule_;
  bool reverse_;
};

}  // namespace pbd::detail
