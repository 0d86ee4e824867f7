// pbd on the peer's BarDemo bar (bench/peer/README.md, "The bar"): loads make_bar.py's file, builds a World with the
// peer's particles (1 kg each, the clamped end pinned) and one Neo-Hookean tet (XPBD, young_poisson(E, ν)) per tet of
// the file, steps it S times under the peer's gravity, follows the tip and prints one line of JSON (bar_common.hpp).
#include "bar_common.hpp"
#include "pbd_particles.hpp"

#include "pbd/constraints/neo_hookean.hpp"
#include "pbd/world.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

namespace {

using peer_bench::Clock;

template <class Real> peer_bench::BarResult run(const peer_bench::BarOptions& o, const peer_bench::Bar& b) {
  using namespace pbd;
  const Clock::time_point t0 = Clock::now();
  World<Real> world;
  // The peer's masses: addRegularTetModel gives every vertex 1 kg (not a density lumped over the tets, as
  // add_tet_body would: there the surface's vertices weigh less than the interior's), the demo pins the i = 0 end.
  peer_bench::add_file_particles(world, b.x, b.mass, b.pinned);

  // One Neo-Hookean tet per tet of the file, corners in the file's (the peer's) order: every one is positively
  // oriented as pbd wants (World::add refuses an inverted one).
  const NeoHookeanMaterial m = young_poisson(o.young, o.poisson);
  const Index set = world.add_constraint_set(Stiffness::xpbd_compliance(m.compliance()));
  world.template reserve<NeoHookeanConstraint<Real>>(b.tets.size());
  for (const auto& t : b.tets) {
    NeoHookeanConstraint<Real> c = blank_constraint<NeoHookeanConstraint<Real>>();
    c.particles = {Index(t[0]), Index(t[1]), Index(t[2]), Index(t[3])};
    c.set = set;
    c.ratio = Real(m.ratio());
    world.add(c, required_fields<NeoHookeanConstraint<Real>>());
  }

  StepParams<Real> params = world.params();
  params.dt = Real(o.dt);
  params.substeps = o.substeps;
  params.iterations = o.iterations;
  params.gravity = Vec3<Real>(Real(0), Real(-9.81), Real(0));  // the peer's Simulation default gravitation
  params.damping = Real(o.damping);                            // 0 unless asked (the peer has none)
  if (!o.solver.empty()) {
    const auto s = parse_solver(o.solver);
    if (!s) throw Error("unknown solver '" + o.solver + "' (one of " + solver_names() + ")");
    params.solver = *s;
  } else {
    params.solver = Solver::colored;
  }
  world.set_params(params);
  if (o.inline_below > 0) {
    // A color smaller than this runs on one thread (pbd's default, 1024, suits the cloth's cheap stretch
    // constraints; a Neo-Hookean tet costs several times more).
    ParallelConfig pc;
    pc.inline_below = std::size_t(o.inline_below);
    pc.min_grain = std::min(pc.min_grain, std::size_t(o.inline_below));
    world.set_parallel_config(pc);
  }

  peer_bench::BarResult r;
  r.engine = "pbd";
  r.precision = sizeof(Real) == 4 ? "float" : "double";
  r.method = "neo-hookean";
  r.solver = std::string(name(params.solver));
  r.particles = std::size_t(world.num_particles());
  r.tets = world.template constraints<NeoHookeanConstraint<Real>>().size();
  r.constraints = r.tets;
  r.colors = (long long)world.num_colors();  // lays out now: set-up, not the first step's cost
  r.threads = tbb::this_task_arena::max_concurrency();
  r.setup_ms = peer_bench::ms_since(t0);

  double integrate = 0, solve = 0;
  const auto tip = [&] {
    const auto p = world.positions();
    return peer_bench::tip_of(b, [&](unsigned i) {
      return peer_bench::Point{double(p(0, i)), double(p(1, i)), double(p(2, i))};
    });
  };
  char made_by[160];
  std::snprintf(made_by, sizeof made_by, "pbd %s, %s solver, %d x %d, E = %g Pa, nu = %g, damping %g", r.precision.c_str(),
                r.solver.c_str(), o.substeps, o.iterations, o.young, o.poisson, o.damping);
  peer_bench::run_bar(
      o, b, r,
      [&] {
        world.step();
        const StepStats& st = world.last_step_stats();
        integrate += st.seconds_integrate;
        solve += st.seconds_solve;
      },
      tip, made_by);
  r.integrate_ms = 1e3 * integrate / o.steps;
  r.solve_ms = 1e3 * solve / o.steps;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const peer_bench::BarOptions o = peer_bench::parse_bar(
      argc, argv,
      "  --solver: serial, serial-colored, colored (default), jacobi, block; --threads: a tbb::task_arena;\n"
      "  --method: neo-hookean (the only one); --stiffness is the peer's shape matching's (ignored here);\n"
      "  --inline-below N: colors of fewer constraints run on one thread, and tasks get at least min(N, 256)\n"
      "  (ParallelConfig::inline_below and min_grain; default 1024 and 256)\n");
  if (!o.method.empty() && o.method != "neo-hookean") {
    std::fprintf(stderr, "pbd_bar: --method: only neo-hookean, got '%s'\n", o.method.c_str());
    return 2;
  }
  try {
    const peer_bench::Bar b = peer_bench::read_bar(o.mesh);
    tbb::task_arena arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic);
    peer_bench::BarResult r;
    arena.execute([&] { r = o.use_double ? run<double>(o, b) : run<float>(o, b); });
    peer_bench::print_bar(o, b, r);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pbd_bar: %s\n", e.what());
    return 1;
  }
  return 0;
}
