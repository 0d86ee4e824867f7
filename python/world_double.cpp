// pbd.WorldDouble: World<double> (world_bindings.hpp).
#include "world_bindings.hpp"

namespace pbd::python {
void bind_world_double(py::module_& m) { bind_world<double>(m, "WorldDouble", "build_world_double"); }
}  // namespace pbd::python
