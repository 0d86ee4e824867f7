#include "pbd/io/finite_state.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

namespace pbd {

template <class Real> void check_finite_state(const World<Real>& world, const std::string& what) {
  const auto x = world.positions();
  const auto v = world.velocities();
  if (x.allFinite() && v.allFinite()) return;  // one pass in the common case; the search below only on failure
  for (Index i = 0; i < world.num_particles(); ++i)
    for (const bool position : {true, false}) {
      const auto c = position ? x.col(i) : v.col(i);
      if (!c.allFinite())
        throw Error(detail::message(what, ": particle ", i, " has a non-finite ", position ? "position" : "velocity",
                                    " (", c[0], ", ", c[1], ", ", c[2], ")"));
    }
}

template void check_finite_state(const World<float>&, const std::string&);
template void check_finite_state(const World<double>&, const std::string&);

}  // namespace pbd
