#pragma once
// How Python holds a World (PyWorld) and runs a step on it with the GIL released; the lifetime rules are in
// module.cpp's design note.
#include "bindings.hpp"

#include "pbd/error.hpp"
#include "pbd/world.hpp"

#include <tbb/task_arena.h>

#include <atomic>
#include <memory>
#include <string>
#include <utility>

namespace pbd::python {

/// A World as Python holds it: the engine's world, its live numpy views and whether it is stepping.
template <class Real> struct PyWorld {
  World<Real> world;
  int views = 0;                       // live views of positions()/velocities(); only touched with the GIL held
  std::atomic<bool> stepping = false;  // a step() runs with the GIL released
  bool has_callback = false;           // a force callback is set (it is host code: not pickled)
  int threads = 0;                     // threads of each step (0: the caller's arena)
  std::unique_ptr<tbb::task_arena> arena;  // the arena of `threads` threads, when threads > 0

  PyWorld() = default;
  explicit PyWorld(World<Real> w) : world(std::move(w)) {}

  /// Runs each step in an arena of n threads (0: in the caller's).
  void set_threads(int n) {
    threads = n;
    arena = n > 0 ? std::make_unique<tbb::task_arena>(n) : nullptr;
  }

  /// The world, unless a step() runs on it (in another thread, or this call comes from its force callback).
  World<Real>& get(const char* call) {
    if (stepping) throw Error(std::string(call) + ": the world is stepping (in another thread, or this is its force callback)");
    return world;
  }
  /// Throws while a view of the storage that adding particles reallocates is alive.
  void check_no_views(const char* call) const {
    if (views)
      throw Error(std::string(call) + ": " + std::to_string(views) +
                  " numpy view(s) of positions()/velocities() are alive and adding particles moves the storage "
                  "they view; delete them (del) or keep copies (.copy()) first");
  }
};

/// Runs f(world) with the GIL released; the world refuses other calls meanwhile.
template <class Real, class F> void run_released(PyWorld<Real>& w, const char* call, F&& f) {
  World<Real>& world = w.get(call);
  struct Done {
    std::atomic<bool>& flag;
    ~Done() { flag = false; }  // after the GIL is taken back (destroyed after `release`)
  } done{w.stepping};
  w.stepping = true;
  // A live view may have been written since the last step: handing out a mutable map makes step() check that every
  // position and velocity is finite first (pbd::Error naming the particle otherwise).
  if (w.views) world.positions();
  py::gil_scoped_release release;
  if (w.arena) w.arena->execute([&] { f(world); });
  else f(world);
}

}  // namespace pbd::python
