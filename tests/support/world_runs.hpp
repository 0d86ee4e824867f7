#pragma once
// What several engine tests measure on a whole world (shape_match_test, soft_body_test, hierarchy_test): its
// momentum and angular momentum, and its final state after stepping on a given number of threads.
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <utility>

namespace pbd::test {

/// Momentum and angular momentum (about the origin) of particles [begin, end) (all of them by default), in double.
/// Every one of them must be movable.
template <class Real>
std::pair<Vec3<double>, Vec3<double>> momenta(const World<Real>& w, Index begin = 0, Index end = ~Index(0)) {
  Vec3<double> p = Vec3<double>::Zero(), l = Vec3<double>::Zero();
  for (Index i = begin; i < std::min(end, w.num_particles()); ++i) {
    const double m = 1 / double(w.inverse_masses()[i]);
    const Vec3<double> v = w.velocities().col(i).template cast<double>();
    p += m * v;
    l += m * Vec3<double>(w.positions().col(i).template cast<double>()).cross(v);
  }
  return {p, l};
}

/// Step parameters of the fiber and tear tests: 1 ms steps of `substeps` × `iterations` under `solver`, no gravity.
template <class Real> StepParams<Real> weightless(Solver solver, int substeps, int iterations) {
  StepParams<Real> p;
  p.dt = Real(1e-3);
  p.substeps = substeps;
  p.iterations = iterations;
  p.gravity = Vec3<Real>::Zero();
  p.solver = solver;
  return p;
}

/// Steps a copy of `w` `steps` times in a task_arena of `threads` threads, validates it and returns its position hash.
template <class Real> std::uint64_t run_on(World<Real> w, int threads, int steps) {
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (int i = 0; i < steps; ++i) w.step();
  });
  w.validate();
  return position_hash(w);
}

}  // namespace pbd::test
