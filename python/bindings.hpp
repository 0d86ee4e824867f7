#pragma once
// The pieces of the Python module pbd (module.cpp says what is bound and the lifetime rules): each bind_* adds its
// names to the module.
#include <pybind11/pybind11.h>

namespace pbd::python {

namespace py = pybind11;

void bind_params(py::module_& m);        // params_bindings.cpp: Stiffness, Solver, StepParams, Chebyshev, ...
void bind_results(py::module_& m);       // results_bindings.cpp: StepStats, Violation, Energy, FiberBreak, ...
void bind_scene(py::module_& m);         // scene_bindings.cpp: Scene, load_scene, parse_scene
void bind_world_float(py::module_& m);   // world_float.cpp: World, build_world and the metrics on World
void bind_world_double(py::module_& m);  // world_double.cpp: WorldDouble, build_world_double, the metrics on it
void bind_io(py::module_& m);            // io_bindings.cpp: data_dir, load_scene, frames, mesh generators (after the worlds)
void bind_faults(py::module_& m);         // fault_bindings.cpp: _inject_fault, _clear_fault (tests only)
void bind_tets(py::module_& m);          // tet_bindings.cpp: TetMesh, NeoHookeanMaterial, Body, add_tet_body (after the worlds)

}  // namespace pbd::python
