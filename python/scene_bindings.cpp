// Scenes: pbd.parse_scene(text, source) and io_bindings.cpp's load_scene(name_or_path) give a Scene (its metadata and precision-free
// description); pbd.build_world / build_world_double (world_bindings.hpp) make a World of it.
#include "bindings.hpp"
#include "signature.hpp"

#include "pbd/io/scene.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

namespace pbd::python {

void bind_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", "A loaded scene: metadata and the world it describes (build it with build_world).")
      .def_readonly("name", &Scene::name, "the scene's name")
      .def_readonly("description", &Scene::description, "one line saying what it shows")
      .def_readonly("source", &Scene::source, "file it came from (or the source given to parse_scene)")
      .def_readonly("steps", &Scene::steps, "the scene's suggested number of steps")
      .def_readonly("primary_error", &Scene::primary_error, "the error its results are judged by ('' = not stated)")
      .def_property_readonly(
          "dt", [](const Scene& s) { return s.world.params.dt; },
          "its time step (s) in double, as written (a float world rounds it; FrameSeries(dt=) times frames by it)")
      .def_property_readonly(
          "triangles",
          [](const Scene& s) {
            py::array_t<std::uint32_t> t({py::ssize_t(s.triangles.size()), py::ssize_t(3)});
            auto r = t.mutable_unchecked<2>();
            for (std::size_t i = 0; i < s.triangles.size(); ++i)
              for (int k = 0; k < 3; ++k) r(py::ssize_t(i), k) = s.triangles[i][k];
            return t;
          },
          "surface triangles of its bodies, (M, 3) particle indices (a copy)")
      .def("__repr__", [](const Scene& s) { return "<pbd.Scene " + s.name + " from " + s.source + ">"; }, sig);
  m.def("parse_scene", &parse_scene, py::arg("text"), py::arg("source") = "<string>",
        "Parses scene JSON text; `source` names it in error messages.", sig);
}

}  // namespace pbd::python
