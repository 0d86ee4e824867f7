#pragma once
/// \file fiber_state.hpp
/// What a host reads of the constraints that follow a stress–strain curve (constraints/fiber.hpp, tet_fiber.hpp)
/// after a step: each one's strains and force (World::fibers, World::material_readings), and those the step broke
/// (World::last_breaks).
#include "pbd/types.hpp"

#include <array>
#include <cstdint>

namespace pbd {

/// One fiber (or tet fiber) after a step.
struct FiberReading {
  double strain = 0.0;   ///< total strain l/L0 − 1 at the current positions
  double plastic = 0.0;  ///< plastic strain ε_p: its rest length has grown to L0·(1 + ε_p)
  /// Tension in N the last step's last sub-step left in a fiber, −λ/h² (negative: compressed); for a tet fiber, the
  /// stress along it in Pa, −λ/(h²·V0) (its type's kForceUnit). NaN where λ says nothing: before the first step,
  /// and in a PBD set (k, no compliance), whose λ is never kept.
  double force = 0.0;
};

/// One fiber or tet fiber a step broke (it reached its set's rupture strain at the step's end).
struct FiberBreak {
  std::int64_t step = 0;        ///< the world's step count after that step, round(time / dt)
  double time = 0.0;            ///< the world's time after that step, s
  const char* type = "fiber";   ///< its constraint type's name ("fiber", "tet_fiber")
  Index fiber = 0;              ///< its index among the constraints of its type just before it was removed
  Index set = 0;                ///< its constraint set
  std::array<Index, 4> particles{};  ///< its particles, the first `arity` of these
  int arity = 2;                ///< how many particles it has (2 for a fiber, 4 for a tet fiber)
  double strain = 0.0;          ///< its total strain at the break
  double plastic = 0.0;         ///< its plastic strain at the break
  double force = 0.0;           ///< what it carried at the break: N for a fiber, Pa for a tet fiber (FiberReading)
};

/// A particle a tear added (World::add_surface): a copy of `from` that took its place on one side of the tear.
struct TornParticle {
  Index particle = 0;  ///< the new particle's index
  Index from = 0;      ///< the particle it was copied from
};

}  // namespace pbd
