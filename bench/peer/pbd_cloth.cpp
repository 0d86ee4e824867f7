// pbd on the peer's ClothDemo cloth (bench/peer/README.md): loads make_cloth.py's file, builds a World with the
// peer's distance (k = 1) and dihedral (k = 0.01) constraints as plain PBD stiffness (the peer scales each
// correction by k), steps it S times and prints one line of JSON (cloth_common.hpp).
#include "cloth_common.hpp"
#include "pbd_particles.hpp"

#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <cstdio>
#include <exception>
#include <span>
#include <vector>

namespace {

using peer_bench::Clock;

template <class Real> peer_bench::Result run(const peer_bench::Options& o, const peer_bench::Cloth& c) {
  using namespace pbd;
  const Clock::time_point t0 = Clock::now();
  World<Real> world;
  peer_bench::add_file_particles(world, c.x, c.mass, c.pinned);

  // The peer's model: DistanceConstraint and DihedralConstraint both return k·(the full projection), with k fixed
  // per constraint whatever the iteration count: pbd's StiffnessMode::pbd (not the iteration-independent k', not
  // XPBD compliance).
  const Index distance = world.add_constraint_set(Stiffness::pbd_k(o.k_distance));
  const Index bending = world.add_constraint_set(Stiffness::pbd_k(o.k_bending));
  world.template reserve<StretchConstraint<Real>>(c.edges.size());
  world.template reserve<BendingConstraint<Real>>(c.quads.size());
  for (const auto& e : c.edges) {
    const double dx = c.x[e[1]][0] - c.x[e[0]][0], dy = c.x[e[1]][1] - c.x[e[0]][1], dz = c.x[e[1]][2] - c.x[e[0]][2];
    world.add_stretch(e[0], e[1], distance, Real(std::sqrt(dx * dx + dy * dy + dz * dz)));
  }
  // The peer's DihedralConstraint is on (opposite p0, opposite p1, edge e0, edge e1); pbd's add_bending takes the
  // shared edge first. Rest angle: the current one (flat: π in pbd's convention, 0 in the peer's; same constraint).
  for (const auto& q : c.quads) world.add_bending(q[2], q[3], q[0], q[1], bending);

  if (o.tethers) {
    // World::add_tethers (issue 44), where this build has it: every particle tethered to the nearest pin.
    if constexpr (requires(World<Real>& w, std::span<const Index> body) { w.add_tethers(body); }) {
      std::vector<Index> body(std::size_t(world.num_particles()));
      for (std::size_t i = 0; i < body.size(); ++i) body[i] = Index(i);
      world.add_tethers(std::span<const Index>(body));
    } else {
      throw Error("--tethers: this build has no World::add_tethers");
    }
  }
  StepParams<Real> params = world.params();
  if (o.hierarchy) {
    // StepParams::hierarchy (issue 44), where this build has it, with its default levels.
    if constexpr (requires(StepParams<Real>& p) { p.hierarchy.enabled = true; }) params.hierarchy.enabled = true;
    else throw Error("--hierarchy: this build has no StepParams::hierarchy");
  }
  params.dt = Real(o.dt);
  params.substeps = o.substeps;
  params.iterations = o.iterations;
  params.gravity = Vec3<Real>(Real(0), Real(-9.81), Real(0));  // the peer's Simulation default gravitation
  params.damping = 0;
  if (!o.solver.empty()) {
    const auto s = parse_solver(o.solver);
    if (!s) throw Error("unknown solver '" + o.solver + "' (one of " + solver_names() + ")");
    params.solver = *s;
  } else {
    params.solver = Solver::colored;  // the fastest Gauss-Seidel solver on this cloth (docs/performance.md)
  }
  world.set_params(params);

  peer_bench::Result r;
  r.engine = "pbd";
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.solver = std::string(name(params.solver));
  r.particles = world.num_particles();
  r.distance = world.template constraints<StretchConstraint<Real>>().size();
  r.bending = world.template constraints<BendingConstraint<Real>>().size();
  r.colors = (long long)world.num_colors();  // lays out (colors or blocks) now: set-up, not the first step's cost
  r.threads = tbb::this_task_arena::max_concurrency();
  r.setup_ms = peer_bench::ms_since(t0);

  // The step's phase timers (StepStats): prediction and velocity update, sweeps, and of the sweeps the threads'
  // waiting for one another; the steps whose sweeps more than one thread ran.
  double integrate = 0, solve = 0, wait = 0;
  int shared = 0;
  auto error = [&] {
    const auto p = world.positions();
    return peer_bench::stretch(c, [&](unsigned i) {
      return std::array<double, 3>{double(p(0, i)), double(p(1, i)), double(p(2, i))};
    });
  };
  r.ms_per_step = peer_bench::timed_steps(
      o, r,
      [&](int) {
        world.step();
        const StepStats& st = world.last_step_stats();
        integrate += st.seconds_integrate;
        solve += st.seconds_solve;
        wait += st.seconds_waiting;
        shared += st.solve_threads > 1 ? 1 : 0;
      },
      [&] { return error().rms; });
  r.integrate_ms = 1e3 * integrate / o.steps;
  r.solve_ms = 1e3 * solve / o.steps;
  r.wait_ms = 1e3 * wait / o.steps;
  r.shared_steps = shared;

  r.error = error();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const peer_bench::Options o = peer_bench::parse(
      argc, argv,
      "  --solver: serial, serial-colored, colored (default), jacobi, block; --threads: a tbb::task_arena;\n"
      "  --tethers, --hierarchy: issue 44's long-range attachments and hierarchy, where this build has them\n");
  try {
    const peer_bench::Cloth c = peer_bench::read_cloth(o.mesh);
    tbb::task_arena arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic);
    peer_bench::Result r;
    arena.execute([&] { r = o.use_double ? run<double>(o, c) : run<float>(o, c); });
    peer_bench::print(o, c, r);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pbd_cloth: %s\n", e.what());
    return 1;
  }
  return 0;
}
