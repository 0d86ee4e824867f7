// Parameters and results shared by both precisions: Stiffness, Solver, SweepOrder, StepParams, StepStats,
// ContactMaterial, PressureSchedule, Violation, NamedViolation, Energy.
#include "bindings.hpp"
#include "params.hpp"

#include "pbd/constraints/volume.hpp"
#include "pbd/fiber_state.hpp"
#include "pbd/metrics.hpp"
#include "pbd/stiffness.hpp"

#include <pybind11/stl.h>

#include <sstream>

namespace pbd::python {

void bind_params(py::module_& m) {
  py::enum_<StiffnessMode>(m, "StiffnessMode", "Formulation of a constraint set's stiffness.")
      .value("pbd", StiffnessMode::pbd, "each projection scaled by k")
      .value("pbd_iteration_independent", StiffnessMode::pbd_iteration_independent,
             "scaled by k' = 1 - (1 - k)^(1/iterations)")
      .value("xpbd", StiffnessMode::xpbd, "XPBD compliance alpha (m/N for stretch)")
      .value("material", StiffnessMode::material, "a fiber's stress-strain curve (Material)");

  py::class_<Material>(m, "Material",
                       "A fiber's stress-strain curve (pbd/material.hpp): a quadratic toe up to toe_strain, a linear "
                       "part of slope stiffness (N per unit strain), yield at yield_strain with hardening (N per unit "
                       "plastic strain), rupture at rupture_strain (total strain); inf: never.")
      .def(py::init([](double stiffness, double toe_strain, double yield_strain, double hardening, double rupture_strain) {
             return Material{stiffness, toe_strain, yield_strain, hardening, rupture_strain};
           }),
           py::arg("stiffness"), py::arg("toe_strain") = 0.0, py::arg("yield_strain") = Material::kNever,
           py::arg("hardening") = 0.0, py::arg("rupture_strain") = Material::kNever)
      .def_readwrite("stiffness", &Material::stiffness, "k > 0, N per unit strain: the linear part's slope (E*A)")
      .def_readwrite("toe_strain", &Material::toe_strain, "where the toe ends (0: linear from the start)")
      .def_readwrite("yield_strain", &Material::yield_strain, "elastic strain at which it yields (inf: never)")
      .def_readwrite("hardening", &Material::hardening, "N per unit plastic strain: how the yield force grows")
      .def_readwrite("rupture_strain", &Material::rupture_strain, "total strain at which it breaks (inf: never)")
      .def("force", &Material::force, py::arg("elastic_strain"), "force in N at an elastic strain")
      .def("loading_force", &Material::loading_force, py::arg("strain"),
           "force in N of a fiber pulled monotonically from rest to a total strain")
      .def("__repr__", [](const Material& x) {
        std::ostringstream o;
        o << "pbd.Material(stiffness=" << x.stiffness << ", toe_strain=" << x.toe_strain << ", yield_strain="
          << x.yield_strain << ", hardening=" << x.hardening << ", rupture_strain=" << x.rupture_strain << ")";
        return o.str();
      });

  py::class_<Stiffness>(m, "Stiffness", "Stiffness of one constraint set (make one with pbd_k, iteration_independent or xpbd_compliance).")
      .def_readonly("mode", &Stiffness::mode, "formulation (StiffnessMode)")
      .def_readonly("k", &Stiffness::k, "PBD stiffness in [0, 1] (pbd modes)")
      .def_readonly("compliance", &Stiffness::compliance, "XPBD compliance alpha >= 0, inverse stiffness in SI units")
      .def_readonly("material", &Stiffness::material, "the fibers' stress-strain curve (material mode)")
      .def_static("pbd_k", &Stiffness::pbd_k, py::arg("k"), "PBD stiffness k in [0, 1]: each projection scaled by k")
      .def_static("iteration_independent", &Stiffness::iteration_independent, py::arg("k"),
                  "PBD stiffness k in [0, 1] that a whole step achieves, whatever the iterations")
      .def_static("xpbd_compliance", &Stiffness::xpbd_compliance, py::arg("alpha"),
                  "XPBD compliance alpha >= 0 (inverse stiffness, SI units; 0 = rigid)")
      .def_static("fiber", &Stiffness::fiber, py::arg("material"),
                  "a stress-strain curve (Material) that the set's fibers follow, yield along and break at")
      .def("__repr__", [](const Stiffness& s) {
        std::ostringstream o;
        if (s.mode == StiffnessMode::material) o << "pbd.Stiffness.fiber(...)";
        else if (s.mode == StiffnessMode::xpbd) o << "pbd.Stiffness.xpbd_compliance(" << s.compliance << ")";
        else o << "pbd.Stiffness." << (s.mode == StiffnessMode::pbd ? "pbd_k(" : "iteration_independent(") << s.k << ")";
        return o.str();
      });

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
        o << "), strain=" << x.strain << ", force=" << x.force << ")";
        return o.str();
      });

  py::enum_<Solver>(m, "Solver", "The constraint solver step() runs.")
      .value("serial", Solver::serial, "reference Gauss-Seidel in insertion order, one thread")
      .value("serial_colored", Solver::serial_colored, "Gauss-Seidel in color order on one thread (colored's bits)")
      .value("colored", Solver::colored, "Gauss-Seidel color after color, each color in parallel")
      .value("jacobi", Solver::jacobi, "Jacobi with split masses, over-relaxed by jacobi_omega")
      .value("block", Solver::block, "block Gauss-Seidel: blocks of particles in parallel, then boundary colors");

  py::enum_<SweepOrder>(m, "SweepOrder", "Order of the Gauss-Seidel sweeps.")
      .value("forward", SweepOrder::forward, "every sub-step in insertion (color) order")
      .value("symmetric", SweepOrder::symmetric, "odd sub-steps sweep backwards (closed bodies)");

  py::class_<Hierarchy>(m, "Hierarchy", "Hierarchical PBD (Mueller 2008): a coarse-to-fine pass over the stretch "
                                        "constraints before each sub-step's sweeps.")
      .def(py::init<>(), "the defaults: off, 4 levels, 2 parents, 1 sweep per level, slack 0.001, rigid stretch only")
      .def_readwrite("enabled", &Hierarchy::enabled, "run the coarse-to-fine pass")
      .def_readwrite("levels", &Hierarchy::levels, "coarse levels, in [1, 16]")
      .def_readwrite("parents", &Hierarchy::parents, "k: neighbours in the coarser level of every particle left out, in [1, 8]")
      .def_readwrite("sweeps", &Hierarchy::sweeps, "sweeps of each coarse level per pass, in [1, 64]")
      .def_readwrite("slack", &Hierarchy::slack,
                     "strain left to the sweeps, in [0, 0.1]: a coarse constraint pulls only past (1 + slack) x its rest")
      .def_readwrite("compliant", &Hierarchy::compliant,
                     "also coarsen compliant (XPBD alpha > 0) stretch; it then settles shorter than alpha*T")
      .def("__repr__", [](const Hierarchy& h) {
        std::ostringstream o;
        o << "pbd.Hierarchy(enabled=" << (h.enabled ? "True" : "False") << ", levels=" << h.levels
          << ", parents=" << h.parents << ", sweeps=" << h.sweeps << ", slack=" << h.slack
          << ", compliant=" << (h.compliant ? "True" : "False") << ")";
        return o.str();
      });

  py::class_<StepParamsPy>(m, "StepParams",
                           "Parameters of step() (a copy: read World.params, change it, assign it back).")
      .def(py::init<>(), "the defaults: dt 1/60 s, 1 substep, 10 iterations, gravity (0, 0, -9.81), colored solver")
      .def_readwrite("dt", &StepParamsPy::dt, "time step in s, > 0")
      .def_readwrite("substeps", &StepParamsPy::substeps, "sub-steps per step, >= 1")
      .def_readwrite("iterations", &StepParamsPy::iterations, "sweeps per sub-step, >= 0")
      .def_readwrite("gravity", &StepParamsPy::gravity, "acceleration of every movable particle, m/s^2 (3 numbers)")
      .def_readwrite("damping", &StepParamsPy::damping, "velocity damping rate in 1/s, >= 0")
      .def_readwrite("collision_margin", &StepParamsPy::collision_margin, "contact generation distance in m, >= 0")
      .def_readwrite("solver", &StepParamsPy::solver, "which solver step() runs (Solver)")
      .def_readwrite("sweep_order", &StepParamsPy::sweep_order, "Gauss-Seidel sweep order (SweepOrder)")
      .def_readwrite("jacobi_omega", &StepParamsPy::jacobi_omega, "Jacobi over-relaxation factor, in (0, 2)")
      .def_readwrite("hierarchy", &StepParamsPy::hierarchy, "hierarchical PBD settings (Hierarchy; off by default)")
      .def("__repr__", [](const StepParamsPy& p) {
        std::ostringstream o;
        o << "pbd.StepParams(dt=" << p.dt << ", substeps=" << p.substeps << ", iterations=" << p.iterations
          << ", solver=" << name(p.solver) << ")";
        return o.str();
      });

  py::class_<Violation>(m, "Violation", "RMS and maximum of a normalized violation over the constraints of one type.")
      .def_readonly("rms", &Violation::rms, "root mean square (units of the type: relative, m or rad)")
      .def_readonly("max", &Violation::max, "maximum (units of the type)")
      .def_readonly("count", &Violation::count, "constraints measured")
      .def("__repr__", [](const Violation& v) {
        std::ostringstream o;
        o << "pbd.Violation(rms=" << v.rms << ", max=" << v.max << ", count=" << v.count << ")";
        return o.str();
      });
  py::class_<NamedViolation>(m, "NamedViolation", "The violation of one constraint type.")
      .def_readonly("type", &NamedViolation::type, "constraint type: stretch, bending, area, volume, collision, ...")
      .def_readonly("value", &NamedViolation::value, "its Violation")
      .def_property_readonly("measure", [](const NamedViolation& v) { return std::string(v.measure.key); },
                             "its error measure's key in reports, e.g. stretch_pct")
      .def_property_readonly("unit", [](const NamedViolation& v) { return std::string(v.measure.unit); },
                             "the unit that measure is reported in, e.g. %")
      .def_property_readonly("scale", [](const NamedViolation& v) { return v.measure.scale; },
                             "reported value = violation x scale");

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
                    "per type at the end of the step (list of NamedViolation; only after set_measure_violation(True))");

  py::class_<ContactMaterial<double>>(m, "ContactMaterial", "Friction and restitution of a surface.")
      .def(py::init([](double s, double k, double e) { return ContactMaterial<double>{s, k, e}; }),
           py::arg("static_friction") = 0.0, py::arg("kinetic_friction") = 0.0, py::arg("restitution") = 0.0,
           "a material: friction coefficients >= 0 (dimensionless), restitution in [0, 1]")
      .def_readwrite("static_friction", &ContactMaterial<double>::static_friction, "static friction coefficient >= 0")
      .def_readwrite("kinetic_friction", &ContactMaterial<double>::kinetic_friction, "kinetic friction coefficient >= 0")
      .def_readwrite("restitution", &ContactMaterial<double>::restitution, "restitution in [0, 1]");

  py::class_<PressureSchedule>(m, "PressureSchedule", "Target volume factor of a volume constraint over time.")
      .def(py::init([](double from, double to, double duration) { return PressureSchedule{from, to, duration}; }),
           py::arg("from_") = 1.0, py::arg("to") = 1.0, py::arg("duration") = 0.0,
           "factor from_ at t = 0 ramping linearly to `to` over duration s")
      .def_readwrite("from_", &PressureSchedule::from, "pressure factor at t = 0")
      .def_readwrite("to", &PressureSchedule::to, "pressure factor from t = duration on")
      .def_readwrite("duration", &PressureSchedule::duration, "seconds of the linear ramp, >= 0")
      .def("at", &PressureSchedule::at, py::arg("t"), "the pressure factor at time t in s");

  py::class_<Energy>(m, "Energy", "Kinetic and gravitational potential energy of the movable particles, J.")
      .def_readonly("kinetic", &Energy::kinetic, "sum of 1/2 m |v|^2, J")
      .def_readonly("potential", &Energy::potential, "-sum of m g.x, J")
      .def_property_readonly("total", &Energy::total, "kinetic + potential, J");
}

}  // namespace pbd::python
