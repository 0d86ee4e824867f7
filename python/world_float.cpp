// pbd.World: World<float>, the fast default (world_bindings.hpp).
#include "world_bindings.hpp"

namespace pbd::python {
void bind_world_float(py::module_& m) {
  bind_world<float>(m, "World", "build_world");
  m.attr("PINNED") = std::numeric_limits<double>::infinity();  // kPinned of either precision
}
}  // namespace pbd::python
