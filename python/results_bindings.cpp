// Results shared by both precisions: StepStats, Violation, NamedViolation, Energy, FiberBreak; each with a repr
// that shows its fields.
#include "bindings.hpp"
#include "repr.hpp"
#include "signature.hpp"

#include "pbd/fiber_state.hpp"
#include "pbd/metrics.hpp"
#include "pbd/step_params.hpp"

#include <pybind11/stl.h>

#include <sstream>

namespace pbd::python {

namespace {

std::string violation_repr(const Violation& v) {
  return fields_repr("Violation", {{"rms", py_repr(v.rms)}, {"max", py_repr(v.max)}, {"count", py_repr(v.count)}});
}

std::string named_violation_repr(const NamedViolation& v) {
  return fields_repr("NamedViolation", {{"type", py_repr(v.type)}, {"value", violation_repr(v.value)},
                                        {"measure", py_repr(std::string(v.measure.key))}});
}

std::string stats_repr(const StepStats& s) {
  std::string violation = "[";
  for (std::size_t i = 0; i < s.violation.size(); ++i) violation += (i ? ", " : "") + named_violation_repr(s.violation[i]);
  violation += "]";
  return fields_repr("StepStats",
                     {{"seconds", py_repr(s.seconds)}, {"seconds_integrate", py_repr(s.seconds_integrate)},
                      {"seconds_collisions", py_repr(s.seconds_collisions)}, {"seconds_coloring", py_repr(s.seconds_coloring)},
                      {"seconds_solve", py_repr(s.seconds_solve)}, {"seconds_hierarchy", py_repr(s.seconds_hierarchy)},
                      {"seconds_waiting", py_repr(s.seconds_waiting)}, {"solve_threads", py_repr(s.solve_threads)},
                      {"substeps", py_repr(s.substeps)}, {"sweeps", py_repr(s.sweeps)}, {"colors", py_repr(s.colors)},
                      {"chebyshev_fallbacks", py_repr(s.chebyshev_fallbacks)}, {"chebyshev_rho", py_repr(s.chebyshev_rho)},
                      {"collisions", py_repr(s.collisions)}, {"violation", violation}});
}

}  // namespace

void bind_results(py::module_& m) {
  py::class_<FiberBreak>(m, "FiberBreak", "A fiber or tet fiber a step broke: it reached its set's rupture strain.")
      .def_readonly("step", &FiberBreak::step, "the world's step count after that step")
      .def_readonly("time", &FiberBreak::time, "the world's time after that step, s")
      .def_property_readonly("type", [](const FiberBreak& x) { return std::string(x.type); },
                             "its constraint type: 'fiber' or 'tet_fiber'")
      .def_readonly("fiber", &FiberBreak::fiber, "its index among the constraints of its type just before it was removed")
      .def_readonly("set", &FiberBreak::set, "its constraint set")
      .def_property_readonly("particles",
                             [](const FiberBreak& x) {
                               return std::vector<Index>(x.particles.begin(), x.particles.begin() + x.arity);
                             },
                             "its particles (2 for a fiber, 4 for a tet fiber)")
      .def_property_readonly("a", [](const FiberBreak& x) { return x.particles[0]; }, "its first particle")
      .def_property_readonly("b", [](const FiberBreak& x) { return x.particles[1]; }, "its second particle")
      .def_readonly("strain", &FiberBreak::strain, "its total strain at the break")
      .def_readonly("plastic", &FiberBreak::plastic, "its plastic strain at the break")
      .def_readonly("force", &FiberBreak::force,
                    "what it carried at the break: a fiber's tension in N, a tet fiber's stress in Pa")
      .def("__repr__", [](const FiberBreak& x) {
        std::ostringstream o;
        o << "pbd.FiberBreak(step=" << x.step << ", type='" << x.type << "', fiber=" << x.fiber << ", particles=(";
        for (int i = 0; i < x.arity; ++i) o << (i ? ", " : "") << x.particles[std::size_t(i)];
        o << "), strain=" << py_repr(x.strain) << ", plastic=" << py_repr(x.plastic) << ", force=" << py_repr(x.force) << ")";
        return o.str();
      }, sig);

  py::class_<Violation>(m, "Violation", "RMS and maximum of a normalized violation over the constraints of one type.")
      .def_readonly("rms", &Violation::rms, "root mean square (units of the type: relative, m or rad)")
      .def_readonly("max", &Violation::max, "maximum (units of the type)")
      .def_readonly("count", &Violation::count, "constraints measured")
      .def("__repr__", &violation_repr, sig);
  py::class_<NamedViolation>(m, "NamedViolation", "The violation of one constraint type.")
      .def_readonly("type", &NamedViolation::type, "constraint type: stretch, bending, area, volume, collision, ...")
      .def_readonly("value", &NamedViolation::value, "its Violation")
      .def_property_readonly("measure", [](const NamedViolation& v) { return std::string(v.measure.key); },
                             "its error measure's key in reports, e.g. stretch_pct")
      .def_property_readonly("unit", [](const NamedViolation& v) { return std::string(v.measure.unit); },
                             "the unit that measure is reported in, e.g. %")
      .def_property_readonly("scale", [](const NamedViolation& v) { return v.measure.scale; },
                             "reported value = violation x scale")
      .def("__repr__", &named_violation_repr, sig);

  py::class_<StepStats>(m, "StepStats", "What the last step() did and how long each phase took (wall-clock s).")
      .def_readonly("seconds", &StepStats::seconds, "the whole step, s")
      .def_readonly("seconds_integrate", &StepStats::seconds_integrate, "forces, damping, prediction, velocity update, s")
      .def_readonly("seconds_collisions", &StepStats::seconds_collisions, "generating contacts, s")
      .def_readonly("seconds_coloring", &StepStats::seconds_coloring, "coloring constraints, s")
      .def_readonly("seconds_solve", &StepStats::seconds_solve, "the sweeps, s")
      .def_readonly("seconds_waiting", &StepStats::seconds_waiting, "of seconds_solve: threads waiting at barriers, s")
      .def_readonly("solve_threads", &StepStats::solve_threads, "most threads that ran one sub-step's sweeps")
      .def_readonly("substeps", &StepStats::substeps, "sub-steps taken")
      .def_readonly("sweeps", &StepStats::sweeps, "sweeps taken (substeps x iterations)")
      .def_readonly("colors", &StepStats::colors, "groups of the persistent constraints (0 for serial)")
      .def_readonly("seconds_hierarchy", &StepStats::seconds_hierarchy, "of seconds_solve: the hierarchy's passes")
      .def_readonly("chebyshev_fallbacks", &StepStats::chebyshev_fallbacks, "sub-steps whose Chebyshev acceleration stopped")
      .def_readonly("chebyshev_rho", &StepStats::chebyshev_rho, "rho of the Chebyshev acceleration after the step")
      .def_readonly("collisions", &StepStats::collisions, "collision constraints and particle contacts of the last sub-step")
      .def_readonly("violation", &StepStats::violation,
                    "per type at the end of the step (list of NamedViolation; only after set_measure_violation(True))")
      .def("__repr__", &stats_repr, sig);

  py::class_<Energy>(m, "Energy", "Kinetic and gravitational potential energy of the movable particles, J.")
      .def_readonly("kinetic", &Energy::kinetic, "sum of 1/2 m |v|^2, J")
      .def_readonly("potential", &Energy::potential, "-sum of m g.x, J")
      .def_property_readonly("total", &Energy::total, "kinetic + potential, J")
      .def("__repr__", [](const Energy& e) {
        return fields_repr("Energy", {{"kinetic", py_repr(e.kinetic)}, {"potential", py_repr(e.potential)}});
      }, sig);
}

}  // namespace pbd::python
