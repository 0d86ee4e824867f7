#pragma once
// Copies and pickles of a World:
// - copy.copy and copy.deepcopy make a new World with the engine's copy constructor (World(const World&)): the state
//   and the model as they are, colors and the Chebyshev estimate included, so both step on to the same bits. The
//   force callback (host code) is shared, not copied; the threads setting is copied.
// - pickle stores (precision, time, threads, bytes of describe_world(w)) (world_state.hpp) and unpickling builds the
//   world again (build_world, set_time). A rebuilt world colors its constraints afresh and re-measures a Chebyshev
//   rho it had estimated, so it steps on to the same bits when the world's colors are what a fresh build makes (no
//   removals or tears since it was built) and its Chebyshev rho, if enabled, is given. A world with a force
//   callback refuses to be pickled (host code is not state); clear it first.
#include "signature.hpp"
#include "world_core.hpp"
#include "world_state.hpp"

#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"

#include <memory>
#include <string>

namespace pbd::python {

template <class Real> std::unique_ptr<PyWorld<Real>> copy_world(PyWorld<Real>& w) {
  auto out = std::make_unique<PyWorld<Real>>(w.get("copy"));
  out->has_callback = w.has_callback;
  out->set_threads(w.threads);
  return out;
}

template <class Real> void bind_world_copy(py::class_<PyWorld<Real>>& cls) {
  using W = PyWorld<Real>;
  const char* precision = sizeof(Real) == 4 ? "float32" : "float64";
  cls.def("__copy__", [](W& w) { return copy_world(w); }, "A copy of the world (copy.copy; as deepcopy).", sig);
  cls.def(
      "__deepcopy__", [](W& w, py::dict) { return copy_world(w); }, py::arg("memo"),
      "A copy of the world (copy.deepcopy): state and model as they are; it steps on to the same bits.", sig);
  cls.def(py::pickle(
      [precision](W& w) {
        const World<Real>& world = w.get("pickle");
        if (w.has_callback)
          throw Error("pickle: the world has a force callback, which is host code and not pickled; clear it first "
                      "(set_force_callback(None))");
        return py::make_tuple(precision, world.time(), w.threads, py::bytes(save_description(describe_world(world))));
      },
      [precision](const py::tuple& t) {
        if (t.size() != 4 || py::str(t[0]).cast<std::string>() != precision)
          throw Error(std::string("unpickle: not the state of a ") + (sizeof(Real) == 4 ? "World" : "WorldDouble") +
                      " (" + precision + ")");
        const std::string bytes = t[3].cast<std::string>();
        auto w = std::make_unique<W>(build_world<Real>(load_description(bytes)));
        w->world.set_time(t[1].cast<double>());
        w->set_threads(t[2].cast<int>());
        return w;
      }));
}

}  // namespace pbd::python
