#pragma once
// The hard cases of the stability suite (stability_test.cpp): scene builders and a harness that steps a world with
// one solver, watches every step (finite state, stretch, energy) and prints one greppable summary line:
//   STABILITY case=<name> solver=<serial|colored-1T|colored-2T|jacobi> real=<float|double> steps=<n>
//             max_stretch=<x> max_ke=<J> energy_gain=<J> end=<case-specific measure>
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "world_access.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace pbd::stability {

/// One way of running a case: a solver on a number of threads.
struct SolverRun {
  const char* label;  ///< as printed: serial, colored-1T, colored-2T, jacobi
  Solver solver;
  int threads;        ///< size of the tbb::task_arena step() runs in
};

/// Every case runs with each of these: the serial reference, the colored solver on 1 and 2 threads, Jacobi (on 2
/// threads; its result does not depend on the thread count, which solver_test checks).
inline constexpr std::array<SolverRun, 4> kSolverRuns = {{{"serial", Solver::serial, 1},
                                                          {"colored-1T", Solver::colored, 1},
                                                          {"colored-2T", Solver::colored, 2},
                                                          {"jacobi", Solver::jacobi, 2}}};

/// Forces real fork/join in every color and particle loop even in these small scenes (otherwise every color is
/// under ParallelConfig::inline_below and "2 threads" computes on one), in chunks of 16 so that a color of a few
/// dozen constraints is still split between the threads.
inline constexpr ParallelConfig kAlwaysFork{1, 16};

template <class Real> constexpr const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

/// Largest relative stretch |len − rest| / rest over the stretch constraints with rest > 0 and a movable particle
/// (zero-length ones have no relative stretch, cases that have them measure their length separately; one between
/// two pinned particles can never change, case 7 checks it does nothing).
template <class Real> double max_relative_stretch(const World<Real>& w) {
  const auto x = w.positions();
  const auto inv = w.inverse_masses();
  double worst = 0.0;
  for (const auto& c : test::stretch_of(w)) {
    if (!(c.rest > Real(0)) || (inv[c.particles[0]] == Real(0) && inv[c.particles[1]] == Real(0))) continue;
    worst = std::max(worst, violation(c, x));
  }
  return worst;
}

/// What a run did, measured after every step.
struct Figures {
  int steps = 0;              ///< steps run (a run stops at the first non-finite state)
  int first_nonfinite = -1;   ///< step after which a position or velocity was NaN or infinite, -1 if none
  double max_stretch = 0.0;   ///< max over steps of max_relative_stretch
  double max_ke = 0.0;        ///< max over steps of the kinetic energy, J
  double energy0 = 0.0;       ///< total (kinetic + gravitational) energy before the first step, J
  double max_energy_gain = -std::numeric_limits<double>::infinity();  ///< max over steps of E(t) − E(0), J
  int peak_step = 0;          ///< step (0-based) at which max_ke was reached
  std::vector<double> ke;     ///< kinetic energy after every step
  Energy end;                 ///< energy after the last step
  bool finite() const { return first_nonfinite < 0; }
  /// Largest kinetic energy over steps [begin, end).
  double max_ke_in(int begin, int end) const {
    double m = 0.0;
    for (int s = std::max(begin, 0); s < std::min<int>(end, int(ke.size())); ++s) m = std::max(m, ke[std::size_t(s)]);
    return m;
  }
};

/// Steps `w` `steps` times with `run` (inside a task_arena of run.threads), calling `after_step(w, s)` after each
/// step s (for case-specific per-step measures). Stops early at a non-finite state.
template <class Real, class AfterStep>
Figures simulate(World<Real>& w, const SolverRun& run, int steps, AfterStep&& after_step,
                 const ParallelConfig& config = kAlwaysFork) {
  StepParams<Real> p = w.params();
  p.solver = run.solver;
  w.set_params(p);
  w.set_parallel_config(config);
  Figures f;
  f.energy0 = energy(w).total();
  tbb::task_arena arena(run.threads);
  arena.execute([&] {
    for (int s = 0; s < steps; ++s) {
      w.step();
      f.steps = s + 1;
      if (!w.positions().allFinite() || !w.velocities().allFinite()) {
        f.first_nonfinite = s;
        break;
      }
      const Energy e = energy(w);
      f.ke.push_back(e.kinetic);
      if (e.kinetic > f.max_ke) {
        f.max_ke = e.kinetic;
        f.peak_step = s;
      }
      f.max_energy_gain = std::max(f.max_energy_gain, e.total() - f.energy0);
      f.max_stretch = std::max(f.max_stretch, max_relative_stretch(w));
      after_step(w, s);
    }
  });
  f.end = energy(w);
  return f;
}

/// simulate() without per-step extras.
template <class Real> Figures simulate(World<Real>& w, const SolverRun& run, int steps) {
  return simulate(w, run, steps, [](const World<Real>&, int) {});
}

/// Prints the summary line of one (case, solver, precision); `end` is the case's end-state measure(s), "key=value".
template <class Real>
void print_line(std::string_view name, const SolverRun& run, const Figures& f, const std::string& end) {
  std::printf("STABILITY case=%.*s solver=%s real=%s steps=%d max_stretch=%.4g max_ke=%.4g energy_gain=%.3g end=%s%s\n",
              int(name.size()), name.data(), run.label, real_name<Real>(), f.steps, f.max_stretch, f.max_ke,
              f.max_energy_gain, end.c_str(), f.finite() ? "" : " NONFINITE");
  std::fflush(stdout);
}

/// Tolerance on "the total energy never exceeds its initial value": 1000 ε of the energy scale Σ m (|g||x| + ½|v|²)
/// of the movable particles at the start. The state is rounded to ε|x| in positions and ε|x|/h in velocities, which
/// moves the measured energy by a few ε of that scale; a solver creating energy shows up far above it.
template <class Real> double energy_tolerance(const World<Real>& w) {
  const double g = w.params().gravity.template cast<double>().norm();
  double scale = 0.0;
  for (Index i = 0; i < w.num_particles(); ++i) {
    if (w.inverse_masses()[i] == Real(0)) continue;
    const double m = 1.0 / double(w.inverse_masses()[i]);
    scale += m * (g * w.positions().col(i).template cast<double>().norm() +
                  0.5 * w.velocities().col(i).template cast<double>().squaredNorm());
  }
  return 1000.0 * double(std::numeric_limits<Real>::epsilon()) * scale;
}

/// The steady sag stretch of PBD with few sweeps, from the momentum balance at the pins. Only a projection of a
/// constraint with one pinned particle changes the movable particles' total momentum (every other projection conserves
/// it: Δp_i = w_i ∇_i C Δλ with Σ_i ∇_i C = 0); with k = 1 it moves the partner (mass m_p) by the constraint's error C.
/// At rest, the sweeps of a sub-step must take back the h²·g that gravity added to every movable particle, so
///   iterations · Σ_pinned links m_p C_link ≥ M g h².
/// With every pinned link at the same relative stretch s (C = s·rest):  s = M g h² / (iterations · Σ m_p rest).
/// Jacobi splits each particle's mass among the c constraints touching it (and applies the sum of their corrections),
/// so each link passes on only about 1/c of its error per sweep: its sag is c_max times larger (c_max: the largest
/// count of a movable particle).
/// This is what lets a 1000:1 rope hang at several times its length at one sub-step of 4 sweeps: it is the method,
/// not a failure, and it shrinks as h² with sub-steps.
template <class Real> double sag_stretch(const World<Real>& w) {
  const auto inv = w.inverse_masses();
  const StepParams<Real>& p = w.params();
  const double h = double(p.dt) / p.substeps;
  double sum = 0.0;
  for (const auto& c : test::stretch_of(w)) {
    const bool pin0 = inv[c.particles[0]] == Real(0), pin1 = inv[c.particles[1]] == Real(0);
    if (pin0 == pin1) continue;
    sum += double(c.rest) / double(inv[pin0 ? c.particles[1] : c.particles[0]]);
  }
  double c_max = 1.0;
  if (p.solver == Solver::jacobi) {
    std::vector<int> count(w.num_particles(), 0);
    w.for_each_builtin([&](const auto& array) {
      for (const auto& c : array)
        for (Index i : c.particles) ++count[i];
    });
    for (Index i = 0; i < w.num_particles(); ++i)
      if (inv[i] != Real(0)) c_max = std::max(c_max, double(count[i]));
  }
  const double g = p.gravity.template cast<double>().norm();
  return c_max * movable_mass(w) * g * h * h / (double(p.iterations) * sum);
}

/// Bound on the largest stretch over a run that starts from rest lengths and swings under gravity: 6 × sag_stretch.
/// A pendulum released from the horizontal pulls with 3× its weight at the bottom of its swing (3×), and links away
/// from the pin can carry more error than the pinned ones: a link between two equal particles moves each by half its
/// error, so it needs twice the error to pass on the same correction (2×).
template <class Real> double swing_stretch_bound(const World<Real>& w) { return 6.0 * sag_stretch(w); }

/// Longest shortest path, in rest lengths of stretch constraints, from a movable particle to a pinned one (0 if
/// nothing is pinned): with every constraint stretched by at most s, no particle gets farther than (1 + s) times
/// this from a pin.
template <class Real> double rest_reach(const World<Real>& w) {
  const Index n = w.num_particles();
  std::vector<std::vector<std::pair<Index, double>>> adj(n);
  for (const auto& c : test::stretch_of(w)) {
    adj[c.particles[0]].push_back({c.particles[1], double(c.rest)});
    adj[c.particles[1]].push_back({c.particles[0], double(c.rest)});
  }
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (Index i = 0; i < n; ++i)
    if (w.inverse_masses()[i] == Real(0)) {
      dist[i] = 0.0;
      queue.push({0.0, i});
    }
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for (const auto& [j, l] : adj[i])
      if (d + l < dist[j]) {
        dist[j] = d + l;
        queue.push({dist[j], j});
      }
  }
  double reach = 0.0;
  for (Index i = 0; i < n; ++i)
    if (w.inverse_masses()[i] != Real(0)) reach = std::max(reach, dist[i]);
  return reach;
}

/// Shortest rest length of a stretch constraint with a movable particle.
template <class Real> double min_rest_length(const World<Real>& w) {
  double l = std::numeric_limits<double>::infinity();
  for (const auto& c : test::stretch_of(w))
    if (c.rest > Real(0)) l = std::min(l, double(c.rest));
  return l;
}

/// "%.4g" of a value, for the end= field.
inline std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// Largest |x_i − c| over the particles: how far the body reached from a point.
template <class Real> double max_distance_from(const World<Real>& w, const Eigen::Vector3d& c) {
  double r = 0.0;
  for (Index i = 0; i < w.num_particles(); ++i)
    r = std::max(r, (w.positions().col(i).template cast<double>() - c).norm());
  return r;
}

/// Centroid of the movable particles (equal weights per particle), in double.
template <class Real> Eigen::Vector3d centroid(const World<Real>& w) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (Index i = 0; i < w.num_particles(); ++i)
    if (w.inverse_masses()[i] != Real(0)) {
      sum += w.positions().col(i).template cast<double>();
      ++n;
    }
  return n ? Eigen::Vector3d(sum / n) : sum;
}

// ---- Scene builders -------------------------------------------------------------------------------------------

/// Sets the step parameters every builder varies (the rest keep their defaults: dt = 1/60 s, gravity −9.81 z).
template <class Real> void set_sweeps(World<Real>& w, int iterations, Real damping, int substeps = 1) {
  StepParams<Real> p;
  p.iterations = iterations;
  p.substeps = substeps;
  p.damping = damping;
  w.set_params(p);
}

/// Case 1: a horizontal rope of `particles` 1 kg particles over 1 m, pinned at (0, 0, 2), its free end 1000 kg,
/// PBD k = 1, released from rest; `iterations` sweeps, `substeps` sub-steps of 1/60 s, air damping 1/s.
template <class Real> World<Real> heavy_rope(int particles, int iterations, int substeps) {
  World<Real> w;
  RopeOptions o;
  o.particles = particles;
  o.length = 1.0;
  o.mass = 1.0;
  o.end_mass = 1000.0;
  o.origin = {0.0, 0.0, 2.0};
  o.direction = {1.0, 0.0, 0.0};
  add_rope(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  set_sweeps(w, iterations, Real(1), substeps);
  return w;
}

/// Case 2: an N×N, 1 m, 1 kg cloth pinned at two corners, released horizontally; stretch with `stiffness`
/// (PBD k = 1 or XPBD α = 0); dt = 1/30 s, 1 sub-step, 2 sweeps, damping `damping` 1/s.
template <class Real> World<Real> stiff_cloth(int n, const Stiffness& stiffness, Real damping) {
  World<Real> w;
  ClothOptions o;
  o.resolution = n;
  o.size = 1.0;
  o.mass = 1.0;
  o.origin = {0.0, 0.0, 2.0};
  o.pin = ClothPin::corners;
  add_cloth(w, o, w.add_constraint_set(stiffness));
  StepParams<Real> p;
  p.dt = Real(1) / Real(30);
  p.substeps = 1;
  p.iterations = 2;
  p.damping = damping;
  w.set_params(p);
  return w;
}

}  // namespace pbd::stability

namespace pbd::stability {

/// Case 3a: a rope of welded knots hanging from a pin at (0, 0, 2): knot k = 1..K is two particles a_k, b_k that
/// start coincident at (k·s, 0, 2), welded by a zero-length stretch constraint (rest 0); links b_{k−1}–a_k have rest
/// s (b_0 is the pin). 0.1 kg per particle, PBD k = 1, 10 sweeps, damping 1/s. Returns the weld indices.
template <class Real> World<Real> welded_rope(int knots, double spacing, std::vector<Index>* welds) {
  World<Real> w;
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  Index prev = w.add_particle(Vec3<Real>(0, 0, 2), World<Real>::kPinned);
  for (int k = 1; k <= knots; ++k) {
    const Vec3<Real> at(Real(k * spacing), 0, 2);
    const Index a = w.add_particle(at, Real(0.1)), b = w.add_particle(at, Real(0.1));
    w.add_stretch(prev, a, set, Real(spacing));
    const Index weld = w.add_stretch(a, b, set);  // rest = current distance = 0
    if (welds) welds->push_back(weld);
    prev = b;
  }
  set_sweeps(w, 10, Real(1));
  return w;
}

/// Case 3b: an N×N, 1 m, 1 kg cloth pinned at two corners whose other particles are all moved onto one point (the
/// cloth's centre) after its constraints took their rest lengths from the flat cloth: every constraint between two
/// unpinned particles starts with coincident particles. PBD k = 1, 10 sweeps, damping 1/s. With collapse = false,
/// the same cloth released flat (the reference for the end state).
template <class Real> World<Real> collapsed_cloth(int n, bool collapse = true) {
  World<Real> w;
  ClothOptions o;
  o.resolution = n;
  o.origin = {0.0, 0.0, 2.0};
  add_cloth(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  auto x = w.positions();
  for (Index i = 0; i < w.num_particles(); ++i)
    if (collapse && w.inverse_masses()[i] != Real(0)) x.col(i) = Vec3<Real>(Real(0.5), Real(0.5), Real(2));
  set_sweeps(w, 10, Real(1));
  return w;
}

/// Case 4: an N×N, 1 m, 1 kg cloth mesh (grid_mesh) pinned at the two corners of its edge y = 1, with stretch
/// (PBD k = 1), bending (k = 0.5, rest = flat) and area (k = 1) constraints taken from the flat cloth; then every
/// unpinned particle is moved onto the line y = 0.5, z = 2 (x kept): every triangle has zero area, every bending
/// pair is collinear, and each column of particles is coincident. 10 sweeps, damping 1/s. With squash = false, the
/// same cloth released flat (the reference for the end state).
template <class Real> World<Real> line_cloth(int n, bool squash = true) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.5));
  sets.area = w.add_constraint_set(Stiffness::pbd_k(1.0));
  MeshBodyOptions o;
  o.origin = {0.0, 0.0, 2.0};
  o.mass = 1.0;
  o.pinned = {Index((n - 1) * n), Index(n * n - 1)};
  add_mesh(w, grid_mesh(n, 1.0), o, sets);
  auto x = w.positions();
  for (Index i = 0; i < w.num_particles(); ++i)
    if (squash && w.inverse_masses()[i] != Real(0)) {
      x(1, i) = Real(0.5);
      x(2, i) = Real(2);
    }
  set_sweeps(w, 10, Real(1));
  return w;
}

/// Case 5: an icosphere (radius 0.5, 1 kg, centred at the origin; level 1: 42 vertices, level 2: 162, two blocks of
/// the volume's parallel reduction) with stretch (XPBD α = `stretch_compliance`), bending (PBD k = 0.1) and a volume
/// constraint (PBD k = 1) with the given pressure schedule; no gravity, 4 sub-steps of 5 sweeps, damping 1/s (the
/// set-up of the built-in inflate scene).
template <class Real> World<Real> volume_ball(int level, const PressureSchedule& pressure, double stretch_compliance) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::xpbd_compliance(stretch_compliance));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.1));
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.pressure = pressure;
  add_mesh(w, icosphere_mesh(level, 0.5), {}, sets);
  StepParams<Real> p;
  p.gravity.setZero();
  p.substeps = 4;
  p.iterations = 5;
  p.damping = Real(1);
  w.set_params(p);
  return w;
}

/// 6V of the world's volume constraint 0 (the unit of VolumeConstraint::rest), in double.
template <class Real> double six_volume_of(const World<Real>& w) {
  const auto& v = w.volumes();
  return six_volume<double>(v.triangles, Matrix3X<double>(w.positions().template cast<double>()));
}

}  // namespace pbd::stability

namespace pbd::stability {

/// Case 6: free 1 kg particles shot at a small sphere (radius 5 cm, centre (0, 0, 3)) at ~150 m/s (2.5 m per step,
/// 25 diameters) and at a tilted ground plane at 200–300 m/s (3–5 m per step); gravity on, 10 sweeps.
template <class Real> World<Real> fast_particles(unsigned seed, int per_target) {
  World<Real> w;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < per_target; ++i)  // at the ball, from above, slightly off-centre
    w.add_particle(Vec3<Real>(Real(0.01 * u(rng)), Real(0.01 * u(rng)), Real(6)), Real(1),
                   Vec3<Real>(Real(3 * u(rng)), Real(3 * u(rng)), Real(-150)));
  for (int i = 0; i < per_target; ++i)  // at the ground, spread out
    w.add_particle(Vec3<Real>(Real(u(rng)), Real(u(rng)), Real(1 + 0.5 * u(rng))), Real(1),
                   Vec3<Real>(Real(5 * u(rng)), Real(5 * u(rng)), Real(-250 + 50 * u(rng))));
  w.add_plane(Vec3<Real>(Real(0.1), Real(0.2), Real(1)), Real(0));
  w.add_sphere(Vec3<Real>(0, 0, 3), Real(0.05));
  return w;
}

/// Case 7a: nothing can move. Every particle pinned; stretch (rest ≠ current, and between two coincident particles),
/// anchors off target, bending and area off rest, a volume at twice its rest, in PBD and XPBD sets (α > 0 makes
/// the denominator α̃ > 0, so Δλ is computed but must not move anything); a plane every particle is behind and a
/// sphere around some of them; gravity on.
template <class Real> World<Real> all_pinned() {
  World<Real> w;
  const Index hard = w.add_constraint_set(Stiffness::pbd_k(1.0));
  const Index soft = w.add_constraint_set(Stiffness::pbd_k(0.5));
  const Index xpbd = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
  const Index rigid = w.add_constraint_set(Stiffness::xpbd_compliance(0.0));
  const TriangleMesh ball = icosphere_mesh(0, 0.5);
  MeshBodyOptions o;
  o.origin = {0.0, 0.0, 1.0};
  for (Index i = 0; i < ball.num_vertices(); ++i) o.pinned.push_back(i);
  MeshConstraintSets sets;
  sets.stretch = xpbd;
  sets.bending = soft;
  sets.area = rigid;
  sets.volume = hard;
  sets.pressure = {2.0, 2.0, 0.0};
  const Body body = add_mesh(w, ball, o, sets);
  const Index a = w.add_particle(Vec3<Real>(Real(0.3), Real(0.1), Real(0.2)), World<Real>::kPinned);
  const Index b = w.add_particle(Vec3<Real>(Real(0.3), Real(0.1), Real(0.2)), World<Real>::kPinned);  // on a
  const Index c = w.add_particle(Vec3<Real>(Real(-0.4), Real(0.2), Real(0.1)), World<Real>::kPinned);
  const Index d = w.add_particle(Vec3<Real>(Real(0.1), Real(-0.5), Real(0.3)), World<Real>::kPinned);
  for (Index set : {hard, soft, xpbd, rigid}) {
    w.add_stretch(a, b, set, Real(0.1));  // coincident, rest 0.1
    w.add_stretch(a, c, set, Real(2));    // far from its rest
    w.add_stretch(c, d, set, Real(0));    // zero rest length
    w.add_anchor(d, set, Vec3<Real>(1, 1, 1));
    w.add_bending(a, c, d, body.first_particle, set, Real(1.0));
    w.add_area(a, c, d, set, Real(2));
  }
  w.add_plane(Vec3<Real>(0, 0, 1), Real(10));      // everything is 8+ m behind it
  w.add_sphere(Vec3<Real>(0, 0, 1), Real(0.6));   // the ball's vertices are inside it
  return w;
}

/// Case 7b: an N×N cloth hanging from its two pinned corners, optionally with constraints between the two pinned
/// corners (PBD k = 1 rest 0.5 m and XPBD α = 1e-4 rest 2 m; they are 1 m apart), 10 sweeps.
template <class Real> World<Real> cloth_with_pinned_pair(int n, bool pinned_pair) {
  World<Real> w;
  ClothOptions o;
  o.resolution = n;
  o.origin = {0.0, 0.0, 2.0};
  add_cloth(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  if (pinned_pair) {
    const Index p0 = Index((n - 1) * n), p1 = Index(n * n - 1);
    w.add_stretch(p0, p1, w.add_constraint_set(Stiffness::pbd_k(1.0)), Real(0.5));
    w.add_stretch(p0, p1, w.add_constraint_set(Stiffness::xpbd_compliance(1e-4)), Real(2));
  }
  return w;
}

/// Case 8: an N×N, `size` m, 0.1 kg cloth mesh (grid_mesh, nothing pinned) with stretch constraints (PBD k = 1) over
/// the ground plane z = 0, 2 sweeps, 1 sub-step of 1/60 s.
///  - prestress = false: rest lengths of the flat grid; the cloth starts crumpled (a fixed pattern of
///    ±1 cm bumps around 2 cm height, ±5 mm in the plane), falls, lands and flattens out on the ground. Velocity
///    damping 0.5/s stands in for the drag and friction that hold a real cloth in place: pbd has no friction, and on a
///    frictionless plane a resting body is neutrally stable in translation and rotation, so without any dissipation
///    float rounding alone random-walks it (we measured 0.2–1.9 m of drift over 10^5 undamped float steps).
///  - prestress = true: rest lengths taken from the bumpy shape (no flat embedding satisfies them), no
///    damping: the cloth lies flat on the ground with its constraints in permanent conflict.
template <class Real> World<Real> resting_cloth(int n, double size, bool prestress) {
  World<Real> w;
  TriangleMesh m = grid_mesh(n, size);
  auto bump = [](Index i) { return 0.01 * std::sin(2.3 * double(i)) + 0.02; };
  if (prestress)
    for (Index i = 0; i < m.num_vertices(); ++i) m.positions(2, i) = bump(i);
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::pbd_k(1.0));
  MeshBodyOptions o;
  o.mass = 0.1;
  add_mesh(w, m, o, sets);
  if (!prestress) {
    auto x = w.positions();
    for (Index i = 0; i < w.num_particles(); ++i) {
      x(0, i) += Real(0.005 * std::sin(1.7 * double(i)));
      x(1, i) += Real(0.005 * std::cos(3.1 * double(i)));
      x(2, i) = Real(bump(i));
    }
  }
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
  set_sweeps(w, 2, Real(prestress ? 0.0 : 0.5));
  return w;
}

}  // namespace pbd::stability
