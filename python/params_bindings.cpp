// Parameters shared by both precisions: Material, Stiffness, Solver, SweepOrder, Hierarchy, Chebyshev, StepParams,
// BlockOptions, ContactMaterial, PressureSchedule; each with a repr that shows its fields (results_bindings.cpp has
// the results).
#include "bindings.hpp"
#include "params.hpp"
#include "repr.hpp"
#include "signature.hpp"

#include "pbd/constraints/volume.hpp"
#include "pbd/stiffness.hpp"

#include <pybind11/stl.h>

#include <sstream>

namespace pbd::python {

namespace {

std::string hierarchy_repr(const Hierarchy& h) {
  return fields_repr("Hierarchy", {{"enabled", py_repr(h.enabled)}, {"levels", py_repr(h.levels)},
                                   {"parents", py_repr(h.parents)}, {"sweeps", py_repr(h.sweeps)},
                                   {"slack", py_repr(h.slack)}, {"compliant", py_repr(h.compliant)}});
}

std::string chebyshev_repr(const Chebyshev<double>& c) {
  return fields_repr("Chebyshev", {{"enabled", py_repr(c.enabled)}, {"rho", py_repr(c.rho)}, {"delay", py_repr(c.delay)},
                                   {"max_rho", py_repr(c.max_rho)}, {"diverge", py_repr(c.diverge)}});
}

std::string step_params_repr(const StepParamsPy& p) {
  return fields_repr("StepParams",
                     {{"dt", py_repr(p.dt)}, {"substeps", py_repr(p.substeps)}, {"iterations", py_repr(p.iterations)},
                      {"gravity", py_repr(p.gravity)}, {"damping", py_repr(p.damping)},
                      {"collision_margin", py_repr(p.collision_margin)}, {"solver", enum_repr(p.solver)},
                      {"sweep_order", enum_repr(p.sweep_order)}, {"jacobi_omega", py_repr(p.jacobi_omega)},
                      {"chebyshev", chebyshev_repr(p.chebyshev)}, {"hierarchy", hierarchy_repr(p.hierarchy)}});
}

}  // namespace

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
           py::arg("hardening") = 0.0, py::arg("rupture_strain") = Material::kNever,
           "a curve: stiffness in N per unit strain, the strains dimensionless (inf: never)", sig)
      .def_readwrite("stiffness", &Material::stiffness, "k > 0, N per unit strain: the linear part's slope (E*A)")
      .def_readwrite("toe_strain", &Material::toe_strain, "where the toe ends (0: linear from the start)")
      .def_readwrite("yield_strain", &Material::yield_strain, "elastic strain at which it yields (inf: never)")
      .def_readwrite("hardening", &Material::hardening, "N per unit plastic strain: how the yield force grows")
      .def_readwrite("rupture_strain", &Material::rupture_strain, "total strain at which it breaks (inf: never)")
      .def("force", &Material::force, py::arg("elastic_strain"), "force in N at an elastic strain", sig)
      .def("loading_force", &Material::loading_force, py::arg("strain"),
           "force in N of a fiber pulled monotonically from rest to a total strain", sig)
      .def("__repr__", [](const Material& x) {
        return fields_repr("Material", {{"stiffness", py_repr(x.stiffness)}, {"toe_strain", py_repr(x.toe_strain)},
                                        {"yield_strain", py_repr(x.yield_strain)}, {"hardening", py_repr(x.hardening)},
                                        {"rupture_strain", py_repr(x.rupture_strain)}});
      }, sig);

  py::class_<Stiffness>(m, "Stiffness", "Stiffness of one constraint set (make one with pbd_k, iteration_independent or xpbd_compliance).")
      .def_readonly("mode", &Stiffness::mode, "formulation (StiffnessMode)")
      .def_readonly("k", &Stiffness::k, "PBD stiffness in [0, 1] (pbd modes)")
      .def_readonly("compliance", &Stiffness::compliance, "XPBD compliance alpha >= 0, inverse stiffness in SI units")
      .def_readonly("material", &Stiffness::material, "the fibers' stress-strain curve (material mode)")
      .def_static("pbd_k", &Stiffness::pbd_k, py::arg("k"), "PBD stiffness k in [0, 1]: each projection scaled by k", sig)
      .def_static("iteration_independent", &Stiffness::iteration_independent, py::arg("k"),
                  "PBD stiffness k in [0, 1] that a whole step achieves, whatever the iterations", sig)
      .def_static("xpbd_compliance", &Stiffness::xpbd_compliance, py::arg("alpha"),
                  "XPBD compliance alpha >= 0 (inverse stiffness, SI units; 0 = rigid)", sig)
      .def_static("fiber", &Stiffness::fiber, py::arg("material"),
                  "a stress-strain curve (Material) that the set's fibers follow, yield along and break at", sig)
      .def("__repr__", [](const Stiffness& s) {
        std::ostringstream o;
        if (s.mode == StiffnessMode::material) o << "pbd.Stiffness.fiber(" << py_repr(s.material) << ")";
        else if (s.mode == StiffnessMode::xpbd) o << "pbd.Stiffness.xpbd_compliance(" << py_repr(s.compliance) << ")";
        else o << "pbd.Stiffness." << (s.mode == StiffnessMode::pbd ? "pbd_k(" : "iteration_independent(") << py_repr(s.k) << ")";
        return o.str();
      }, sig);

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
      .def(py::init<>(), "the defaults: off, 4 levels, 2 parents, 1 sweep per level, slack 0.001, rigid stretch only", sig)
      .def_readwrite("enabled", &Hierarchy::enabled, "run the coarse-to-fine pass")
      .def_readwrite("levels", &Hierarchy::levels, "coarse levels, in [1, 16]")
      .def_readwrite("parents", &Hierarchy::parents, "k: neighbours in the coarser level of every particle left out, in [1, 8]")
      .def_readwrite("sweeps", &Hierarchy::sweeps, "sweeps of each coarse level per pass, in [1, 64]")
      .def_readwrite("slack", &Hierarchy::slack,
                     "strain left to the sweeps, in [0, 0.1]: a coarse constraint pulls only past (1 + slack) x its rest")
      .def_readwrite("compliant", &Hierarchy::compliant,
                     "also coarsen compliant (XPBD alpha > 0) stretch; it then settles shorter than alpha*T")
      .def("__repr__", &hierarchy_repr, sig);

  py::class_<Chebyshev<double>>(m, "Chebyshev",
                                "Chebyshev semi-iterative acceleration of each sub-step's sweeps (pbd/step_params.hpp; "
                                "Jacobi, serial-colored, colored and block solvers).")
      .def(py::init<>(), "the defaults: off, rho 0 (measured), delay 4, max_rho 0.999, diverge 2", sig)
      .def_readwrite("enabled", &Chebyshev<double>::enabled, "accelerate the sweeps")
      .def_readwrite("rho", &Chebyshev<double>::rho,
                     "spectral radius of one sweep, in [0, 1); 0: measured by the next sub-step, then kept by the world")
      .def_readwrite("delay", &Chebyshev<double>::delay, "plain sweeps before the first accelerated one, >= 1")
      .def_readwrite("max_rho", &Chebyshev<double>::max_rho, "cap on a measured rho, in (0, 1)")
      .def_readwrite("diverge", &Chebyshev<double>::diverge,
                     "guard, > 1: a sweep whose change exceeds diverge x the smallest so far ends the acceleration")
      .def("__repr__", &chebyshev_repr, sig);

  py::class_<StepParamsPy>(m, "StepParams",
                           "Parameters of step() (a copy: read World.params, change it, assign it back).")
      .def(py::init<>(), "the defaults: dt 1/60 s, 1 substep, 10 iterations, gravity (0, 0, -9.81), colored solver", sig)
      .def_readwrite("dt", &StepParamsPy::dt, "time step in s, > 0")
      .def_readwrite("substeps", &StepParamsPy::substeps, "sub-steps per step, 1 to 100000 (and substeps x max(1, iterations) at most 1e6: pbd/step_limits.hpp)")
      .def_readwrite("iterations", &StepParamsPy::iterations, "sweeps per sub-step, 0 to 100000")
      .def_readwrite("gravity", &StepParamsPy::gravity, "acceleration of every movable particle, m/s^2 (3 numbers)")
      .def_readwrite("damping", &StepParamsPy::damping, "velocity damping rate in 1/s, >= 0")
      .def_readwrite("collision_margin", &StepParamsPy::collision_margin, "contact generation distance in m, >= 0")
      .def_readwrite("solver", &StepParamsPy::solver, "which solver step() runs (Solver)")
      .def_readwrite("sweep_order", &StepParamsPy::sweep_order, "Gauss-Seidel sweep order (SweepOrder)")
      .def_readwrite("jacobi_omega", &StepParamsPy::jacobi_omega, "Jacobi over-relaxation factor, in (0, 2)")
      .def_readwrite("chebyshev", &StepParamsPy::chebyshev, "Chebyshev acceleration of the sweeps (Chebyshev; off by default)")
      .def_readwrite("hierarchy", &StepParamsPy::hierarchy, "hierarchical PBD settings (Hierarchy; off by default)")
      .def("__repr__", &step_params_repr, sig);

  py::class_<BlockOptions>(m, "BlockOptions",
                           "How the block solver splits the particles into blocks (World.blocking): part of the model, "
                           "never of the thread count.")
      .def(py::init([](std::size_t constraints_per_block, bool use_metis) {
             return BlockOptions{constraints_per_block, use_metis};
           }),
           py::arg("constraints_per_block") = 1024, py::arg("use_metis") = true,
           "about constraints_per_block (>= 1) constraints per block; METIS k-way on the particles' adjacency, or "
           "ranges of particle indices (use_metis=False)", sig)
      .def_readwrite("constraints_per_block", &BlockOptions::constraints_per_block, "aim of the partition, >= 1")
      .def_readwrite("use_metis", &BlockOptions::use_metis, "METIS k-way (True) or ranges of particle indices")
      .def("__repr__", [](const BlockOptions& b) {
        return fields_repr("BlockOptions", {{"constraints_per_block", py_repr(b.constraints_per_block)},
                                            {"use_metis", py_repr(b.use_metis)}});
      }, sig);

  py::class_<ContactMaterial<double>>(m, "ContactMaterial", "Friction and restitution of a surface.")
      .def(py::init([](double s, double k, double e) { return ContactMaterial<double>{s, k, e}; }),
           py::arg("static_friction") = 0.0, py::arg("kinetic_friction") = 0.0, py::arg("restitution") = 0.0,
           "a material: friction coefficients >= 0 (dimensionless), restitution in [0, 1]", sig)
      .def_readwrite("static_friction", &ContactMaterial<double>::static_friction, "static friction coefficient >= 0")
      .def_readwrite("kinetic_friction", &ContactMaterial<double>::kinetic_friction, "kinetic friction coefficient >= 0")
      .def_readwrite("restitution", &ContactMaterial<double>::restitution, "restitution in [0, 1]")
      .def("__repr__", [](const ContactMaterial<double>& c) {
        return fields_repr("ContactMaterial", {{"static_friction", py_repr(c.static_friction)},
                                               {"kinetic_friction", py_repr(c.kinetic_friction)},
                                               {"restitution", py_repr(c.restitution)}});
      }, sig);

  py::class_<PressureSchedule>(m, "PressureSchedule", "Target volume factor of a volume constraint over time.")
      .def(py::init([](double from, double to, double duration) { return PressureSchedule{from, to, duration}; }),
           py::arg("from_") = 1.0, py::arg("to") = 1.0, py::arg("duration") = 0.0,
           "factor from_ at t = 0 ramping linearly to `to` over duration s", sig)
      .def_readwrite("from_", &PressureSchedule::from, "pressure factor at t = 0")
      .def_readwrite("to", &PressureSchedule::to, "pressure factor from t = duration on")
      .def_readwrite("duration", &PressureSchedule::duration, "seconds of the linear ramp, >= 0")
      .def("at", &PressureSchedule::at, py::arg("t"), "the pressure factor at time t in s", sig)
      .def("__repr__", [](const PressureSchedule& p) {
        return fields_repr("PressureSchedule",
                           {{"from_", py_repr(p.from)}, {"to", py_repr(p.to)}, {"duration", py_repr(p.duration)}});
      }, sig);
}

}  // namespace pbd::python
