#pragma once
/// \file fiber_state.hpp
/// What a host reads of the fibers (constraints/fiber.hpp) after a step: each fiber's strains and force
/// (World::fibers), and the fibers the step broke (World::last_breaks).
#include "pbd/types.hpp"

#include <cstdint>

namespace pbd {

/// One fiber after a step.
struct FiberReading {
  double strain = 0.0;   ///< total strain l/L0 − 1 at the current positions
  double plastic = 0.0;  ///< plastic strain ε_p: its rest length has grown to L0·(1 + ε_p)
  /// Tension in N the last step's last sub-step left in it, −λ/h² (negative: compressed). NaN where λ says nothing:
  /// before the first step, and in a PBD set (k, no compliance), whose λ is never kept.
  double force = 0.0;
};

/// One fiber a step broke (it reached its set's rupture strain at the step's end).
struct FiberBreak {
  std::int64_t step = 0;  ///< the world's step count after that step, round(time / dt)
  double time = 0.0;      ///< the world's time after that step, s
  Index fiber = 0;        ///< its index among the fibers just before it was removed (insertion order)
  Index set = 0;          ///< its constraint set
  Index a = 0, b = 0;     ///< its two particles
  double strain = 0.0;    ///< its total strain at the break
  double force = 0.0;     ///< the tension it carried at the break, N (as FiberReading::force)
};

/// A particle a tear added (World::add_surface): a copy of `from` that took its place on one side of the tear.
struct TornParticle {
  Index particle = 0;  ///< the new particle's index
  Index from = 0;      ///< the particle it was copied from
};

}  // namespace pbd
