#pragma once
// Stepping a World from Python: step(forces=None), the force callback, the thread count, the step parameters and the
// block solver's partition, and what the last step reports (statistics, fibers, breaks, tears).
//
// Design:
// - step() releases the GIL (run_released). The force callback is called from inside the step at every sub-step; it
//   takes the GIL only for that call. It gets the time and a read-only copy of the positions and returns the forces
//   (N, 3) or None: copies both ways, so no array it sees or returns can outlive the step's storage. An exception it
//   raises leaves World::step (which restores the state the step started from) and reaches the caller as itself.
// - The Python callable is held by a shared_ptr whose deleter takes the GIL: the engine copies and destroys its
//   std::function on any thread, with or without the GIL.
// - threads = N > 0 runs every step in a tbb::task_arena of N threads owned by the Python World (pbd never makes
//   threads: docs/api.md); 0 runs it in the caller's arena (all cores). Results never depend on it.
#include "arrays.hpp"
#include "params.hpp"
#include "signature.hpp"
#include "world_core.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <vector>

namespace pbd::python {

/// The engine's force callback calling a Python callable f(time, positions) -> forces (N, 3) or None.
template <class Real> typename World<Real>::ForceCallback python_force_callback(py::object callable) {
  std::shared_ptr<py::object> f(new py::object(std::move(callable)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
  return [f](double time, Eigen::Ref<const Matrix3X<Real>> x, Eigen::Ref<Matrix3X<Real>> forces) {
    py::gil_scoped_acquire gil;
    const py::ssize_t n = x.cols();
    py::array_t<Real> positions({n, py::ssize_t(3)});
    auto p = positions.template mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) p(i, k) = x(k, i);
    positions.attr("flags").attr("writeable") = false;
    const py::object out = (*f)(time, positions);
    if (out.is_none()) return;
    const auto a = real_array<Real>(out, "force callback: the forces it returned", 3, n);
    const Real* d = a.data();
    for (py::ssize_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) forces(k, i) = d[3 * i + k];
  };
}

template <class Real> void bind_world_step(py::class_<PyWorld<Real>>& cls) {
  using W = PyWorld<Real>;
  cls.def_property(
      "params", [](W& w) { return to_python(w.get("params").params()); },
      [](W& w, const StepParamsPy& p) {
        World<Real>& world = w.get("params");
        world.set_params(to_engine<Real>(p, world.params()));
      },
      "step parameters (StepParams; a copy: change it, then assign it back)");
  cls.def_property(
      "blocking", [](W& w) { return w.get("blocking").blocking(); },
      [](W& w, const BlockOptions& b) { w.get("blocking").set_blocking(b); },
      "how the block solver splits the particles (BlockOptions; a copy: change it, then assign it back)");
  cls.def_property(
      "threads", [](const W& w) { return w.threads; },
      [](W& w, int n) {
        if (n < 0) throw py::value_error("threads must be >= 0 (0: the caller's threads), got " + std::to_string(n));
        w.get("threads");
        w.set_threads(n);
      },
      "threads every step() runs on: N > 0 in an arena of N threads, 0 (the default) on the caller's (all cores); "
      "results are the same bits for any N");
  cls.def(
      "step",
      [](W& w, py::object forces) {
        if (forces.is_none()) return run_released(w, "step", [](World<Real>& world) { world.step(); });
        const Index n = w.get("step").num_particles();
        const auto f = real_array<Real>(forces, "step: forces", 3, py::ssize_t(n));
        const Eigen::Map<const Matrix3X<Real>> F(f.data(), 3, f.shape(0));
        run_released(w, "step", [&](World<Real>& world) { world.step(F); });
      },
      py::arg("forces") = py::none(),
      "Advances the world by params.dt s, with forces (N, 3) in N on the particles if given, and the force callback's "
      "(releases the GIL).",
      sig);
  cls.def(
      "set_force_callback",
      [](W& w, py::object callback) {
        World<Real>& world = w.get("set_force_callback");
        const bool set = !callback.is_none();
        if (set && !PyCallable_Check(callback.ptr()))
          throw py::type_error("set_force_callback: callback must be callable or None");
        world.set_force_callback(set ? python_force_callback<Real>(std::move(callback)) : typename World<Real>::ForceCallback{});
        w.has_callback = set;
      },
      py::arg("callback"),
      "Sets the force callback (None clears it): callback(time, positions) at every sub-step, time in s at its end and "
      "positions a read-only (N, 3) copy in m, returns the forces (N, 3) in N or None. It runs with the GIL held, the rest of "
      "step() without. If it raises, step() raises that exception and the world is as it was before the step.",
      sig);
  cls.def("last_step_stats", [](W& w) { return w.get("last_step_stats").last_step_stats(); },
          "Statistics of the last step() (StepStats, a copy).", sig);
  cls.def("set_measure_violation", [](W& w, bool on) { w.get("set_measure_violation").set_measure_violation(on); },
          py::arg("on"), "Whether step() measures each type's violation into last_step_stats().violation.", sig);
  // Readings of a type that follows a curve (World::material_readings) as a dict of numpy arrays.
  auto readings = [](const std::vector<FiberReading>& r) {
    py::array_t<double> strain(py::ssize_t(r.size())), plastic(py::ssize_t(r.size())), force(py::ssize_t(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) {
      strain.mutable_at(i) = r[i].strain;
      plastic.mutable_at(i) = r[i].plastic;
      force.mutable_at(i) = r[i].force;
    }
    py::dict out;
    out["strain"] = strain;
    out["plastic"] = plastic;
    out["force"] = force;
    return out;
  };
  cls.def(
      "fibers", [readings](W& w) { return readings(w.get("fibers").fibers()); },
      "Each fiber after the last step, in insertion order: a dict of numpy arrays 'strain' (total, l/L0 - 1), "
      "'plastic' (plastic strain) and 'force' (tension in N, -lambda/h^2; NaN before a step or in a PBD set).", sig);
  cls.def(
      "tet_fibers",
      [readings](W& w) {
        return readings(w.get("tet_fibers").template material_readings<TetFiberConstraint<Real>>());
      },
      "Each tet fiber after the last step, in insertion order: a dict of numpy arrays 'strain' (total, |F a0| - 1), "
      "'plastic' (plastic strain) and 'force' (the stress along it in Pa, -lambda/(h^2 V0); NaN before a step or in "
      "a PBD set).", sig);
  cls.def(
      "last_breaks",
      [](W& w) {
        const auto b = w.get("last_breaks").last_breaks();
        return std::vector<FiberBreak>(b.begin(), b.end());
      },
      "The fibers and tet fibers the last step broke (FiberBreak list: fibers first, each type in the order of their "
      "indices just before).", sig);
  cls.def(
      "add_surface",
      [](W& w, const std::vector<std::array<Index, 3>>& triangles) { return w.get("add_surface").add_surface(triangles); },
      py::arg("triangles"),
      "Adds a surface that tears: where fibers on its edges break, the particles along the cut are copied so that "
      "it parts (mass split by the triangles on each side). Returns its index.", sig);
  cls.def(
      "surface",
      [](W& w, Index s) {
        const auto t = w.get("surface").surface(s);
        return std::vector<std::array<Index, 3>>(t.begin(), t.end());
      },
      py::arg("s"), "The triangles of surface s as they are now (particles renamed where it tore).", sig);
  cls.def(
      "last_copies",
      [](W& w) {
        std::vector<std::pair<Index, Index>> out;
        for (const TornParticle& t : w.get("last_copies").last_copies()) out.push_back({t.particle, t.from});
        return out;
      },
      "The particles the last step's tears added, as (particle, copied from) pairs.", sig);
}

}  // namespace pbd::python
