// The Python module `pbd`: the host API of pbd::World<Real> for Python (pybind11), built for /usr/bin/python3.
//
// What is bound (docs/python.md is the reference; python/pbd.pyi the types):
// - pbd.World (World<float>) and pbd.WorldDouble (World<double>): particles, constraint sets and constraints
//   (add_<name>, remove_<name>), colliders, contact bodies, removal and the generators (world_edit.hpp), step
//   parameters, step(forces=None), the force callback and the thread count (world_step.hpp), statistics, validate(),
//   copies and pickles (world_copy.hpp); build_world(scene) / build_world_double(scene) build one from a scene.
// - Parameters and results: Stiffness, Material, Solver, SweepOrder, Hierarchy, Chebyshev, StepParams, BlockOptions,
//   ContactMaterial, PressureSchedule (params_bindings.cpp); StepStats, Violation, NamedViolation, Energy,
//   FiberBreak (results_bindings.cpp); each prints its fields.
// - Scenes and files: parse_scene (scene_bindings.cpp); data_dir, load_scene(name or path), scene_names, FrameSeries,
//   write_obj_frame and the mesh generators (io_bindings.cpp).
// - Soft bodies (tet_bindings.cpp): TetMesh, tet_box_mesh, load_tet_mesh, tetrahedralize, check_tet_mesh,
//   tet_mesh_surface, NeoHookeanMaterial, young_poisson, Body, and World.add_tet_body / WorldDouble.add_tet_body.
// - Metrics, as in metrics.hpp: <name>_violation for each built-in constraint type (stretch_violation, ...),
//   constraint_violations (each NamedViolation with its measure, unit and scale), energy, position_hash; and
//   World.violations(type), one value per constraint.
// - The constraint calls add_<name>(particles..., set, rest values=None), remove_<name>(indices) and <name>_violation
//   are generated from the list of built-in types (constraint_types.hpp): a new type needs no line here.
// - pbd::Error → pbd.Error (a RuntimeError) with the library's message; a bad numpy argument (shape, dtype) is a
//   ValueError naming the call and the argument.
// - Every def ends with `sig` (signature.hpp): a text signature that inspect.signature reads.
//
// Ownership and lifetime:
// - A Python World owns its pbd::World (arrays.hpp, world_bindings.hpp). positions() and velocities() are numpy
//   arrays of shape (N, 3) viewing the engine's storage (3×N column-major = N×3 row-major), no copy, writeable
//   between steps; each holds a token that keeps the World alive and is counted by it. The storage moves only when
//   particles are added, so add_particle(s) raise pbd.Error while any view is alive (del it or take a .copy()).
//   step() keeps positions in their storage (World::step), so a view stays current across steps.
// - Every other result is a copy: inverse_masses(), last_step_stats(), params, Scene.triangles.
// - step() releases the GIL, so distinct worlds step concurrently from Python threads; a force callback takes it back
//   for its own call only. While one world steps, any other call on that world raises pbd.Error (its views may be
//   read, but see values mid-step).
#include "bindings.hpp"

#include "pbd/error.hpp"
#include "pbd/version.hpp"

#include <exception>
#include <string>

namespace {

PyObject* error_type = nullptr;  // pbd.Error, which the module keeps alive

// pbd::Error → pbd.Error with its whole message. PyErr_SetString, which pybind11's own translation calls, decodes the
// message as strict UTF-8 and on failure raises the exception with no message at all: a message quoting a byte of no
// valid UTF-8 sequence (pbd::io escapes those, but a host's own message may not) keeps it as \xNN instead.
void translate_error(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const pbd::Error& e) {
    const std::string what = e.what();
    PyObject* text = PyUnicode_DecodeUTF8(what.data(), Py_ssize_t(what.size()), "backslashreplace");
    PyErr_SetObject(error_type, text);
    Py_XDECREF(text);
  }
}

}  // namespace

PYBIND11_MODULE(pbd, m) {
  namespace py = pybind11;
  // Every def writes its own text signature (signature.hpp), which pybind11's would hide.
  py::options options;
  options.disable_function_signatures();
  m.doc() = "pbd: data-parallel Position Based Dynamics (Python bindings of pbd::World)";
  m.attr("__version__") = pbd::version;
  error_type = py::register_exception<pbd::Error>(m, "Error", PyExc_RuntimeError).ptr();
  py::register_exception_translator(translate_error);  // tried before register_exception's own
  m.attr("Error").attr("__doc__") = "Invalid input to pbd: the message names the offending item (pbd::Error).";
  pbd::python::bind_params(m);
  pbd::python::bind_results(m);
  pbd::python::bind_scene(m);
  pbd::python::bind_world_float(m);
  pbd::python::bind_world_double(m);
  pbd::python::bind_io(m);
  pbd::python::bind_tets(m);  // adds add_tet_body to World and WorldDouble
  pbd::python::bind_faults(m);
}
