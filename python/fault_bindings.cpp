// pbd._inject_fault and pbd._clear_fault: the engine's fault injection (engine/src/fault_injection.hpp), for the tests
// that check a failed step() leaves the world as it was (tests/python/test_step_undo.py). Private: not in pbd.pyi.
#include "bindings.hpp"
#include "signature.hpp"

#include "pbd/detail/fault_injection.hpp"

#include <string>

namespace pbd::python {

void bind_faults(py::module_& m) {
  m.def(
      "_inject_fault",
      [](const std::string& phase, const std::string& kind, int hit) {
        const detail::FaultPhase p = detail::fault_phase_named(phase.c_str());
        if (p == detail::FaultPhase::count) throw py::value_error("_inject_fault: no phase '" + phase + "'");
        if (kind != "error" && kind != "bad_alloc")
          throw py::value_error("_inject_fault: kind must be 'error' or 'bad_alloc', got '" + kind + "'");
        if (hit < 1) throw py::value_error("_inject_fault: hit must be >= 1");
        detail::arm_fault(p, kind == "error" ? detail::FaultKind::error : detail::FaultKind::bad_alloc, hit);
      },
      py::arg("phase"), py::arg("kind") = "error", py::arg("hit") = 1,
      "Tests only: the hit-th time the next steps reach `phase` (predict, contacts, solve, update, step_end, "
      "frame_write), raise pbd.Error (kind 'error') or MemoryError (kind 'bad_alloc'), once.",
      sig);
  m.def(
      "_clear_fault", [] { return detail::disarm_fault(); },
      "Tests only: disarms the injected fault; returns whether it fired.", sig);
}

}  // namespace pbd::python
