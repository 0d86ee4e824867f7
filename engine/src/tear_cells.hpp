#pragma once
// Tearing volumes along broken fibers (private; World::break_fibers). A body of tets reinforced by fibers tears
// where its fibers break: a constraint whose type breaks with fibers (traits.hpp: breaks_with_fibers, the tet
// types) and which holds both ends of a fiber the step broke, or all four corners of a tet fiber it broke
// (constraints/tet_fiber.hpp), leaves the model with it. So the ring of tets around a torn edge, or a tet whose own
// fibers tore, no longer holds its corners together. This is element erosion: the
// particles stay (mass and momentum are untouched) and the frames draw only the tets left, so a crack opens where
// the tets are gone. The rule reads only which fibers broke, not their order nor the thread count.
#include "pbd/detail/model.hpp"
#include "pbd/fiber_state.hpp"

#include <array>
#include <span>
#include <vector>

namespace pbd::detail {

/// Per built-in type, the constraints (by user index, ascending) that break with `breaks`: those of a type that
/// breaks with fibers holding both particles of a broken fiber or all four of a broken tet fiber. Empty when no
/// type breaks with fibers.
template <class Real>
std::array<std::vector<Index>, kNumBuiltinTypes> cells_on_broken_fibers(const Model<Real>& m,
                                                                        std::span<const FiberBreak> breaks);

}  // namespace pbd::detail
