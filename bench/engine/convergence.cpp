// Convergence per sweep: how many sweeps each solver needs, in one step of one sub-step, to come as close to that
// step's converged solution as the serial reference does in S sweeps (S = 16 and 64), and how many sweeps take the
// perturbed 100² cloth to 1e-3 RMS relative stretch with and without Chebyshev acceleration. Not a timing: the
// counts are the same on any machine. Usage: convergence [--quick]  (prints Markdown tables)
//
// Scenes (double precision):
//   cloth    100² grid cloth (stretch k = 1, dihedral bending k = 0.2), two corners pinned, every movable particle
//            moved by up to ±30% of the spacing at random (seed 42), gravity on
//   chain    50 links hanging straight down, the last particle 1000× heavier than the others, at rest, gravity on
//   inflate  the built-in scene at step 60 (mid-inflation), reached with the serial solver
// Error: RMS over particles of |x − x*|, x* the same step solved by the serial reference with 4000 sweeps (m).
#include "pbd/io/build_world.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace pbd;
using W = World<double>;

W cloth(int n) {
  W w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.2));
  MeshBodyOptions o;
  o.origin = {0.0, 0.0, 1.0};
  o.pinned = {Index(n * (n - 1)), Index(n * n - 1)};
  add_mesh(w, grid_mesh(n, 1.0), o, sets);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const double spacing = 1.0 / (n - 1);
  auto x = w.positions();
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    if (w.inverse_masses()[i] != 0) x.col(i) += spacing * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return w;
}

W chain() {
  W w;
  RopeOptions o;
  o.particles = 51;
  o.end_mass = 1000.0;
  o.direction = {0.0, 0.0, -1.0};
  add_rope(w, o, w.add_constraint_set(Stiffness::pbd_k(1.0)));
  return w;
}

W inflate() {
  const Scene scene = load_scene(std::string(PBD_SCENES_DIR) + "/inflate.json");
  W w = build_world<double>(scene.world);
  for (int s = 0; s < 60; ++s) w.step();
  return w;
}

// `w` after one step with the given solver and sweeps (one sub-step); rho ≥ 0: Chebyshev with that ρ (0: estimated).
W stepped(W w, Solver solver, int sweeps, double rho = -1) {
  StepParams<double> p = w.params();
  p.solver = solver;
  p.substeps = 1;
  p.iterations = sweeps;
  p.chebyshev.enabled = rho >= 0;
  p.chebyshev.rho = std::max(rho, 0.0);
  w.set_params(p);
  w.step();
  return w;
}

// The positions after that step.
Eigen::Matrix3Xd solved(const W& w, Solver solver, int sweeps, double rho = -1) {
  return stepped(w, solver, sweeps, rho).positions();
}

double rms_distance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return std::sqrt((a - b).colwise().squaredNorm().mean());
}

// Smallest n in [1, limit] with ok(n), assuming ok is monotone; limit + 1 when none.
int smallest(int limit, const std::function<bool(int)>& ok) {
  if (!ok(limit)) return limit + 1;
  int lo = 0, hi = limit;  // ok(hi), !ok(lo) (lo = 0 never tested)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    (ok(mid) ? hi : lo) = mid;
  }
  return hi;
}

std::string ratio(int n, int s, int limit) {
  char buf[64];
  if (n > limit) std::snprintf(buf, sizeof buf, "> %d (> %.2f×)", limit, double(limit) / s);
  else std::snprintf(buf, sizeof buf, "%d (%.2f×)", n, double(n) / s);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  struct Case {
    const char* name;
    W world;
  };
  std::vector<Case> cases;
  cases.push_back({"cloth 100²", cloth(quick ? 40 : 100)});
  cases.push_back({"chain 50 links, 1000:1", chain()});
  cases.push_back({"inflate (step 60)", inflate()});
  const Solver solvers[] = {Solver::colored, Solver::block, Solver::jacobi};
  std::printf("## Sweeps to reach the serial reference's distance to the converged step (one sub-step)\n\n");
  std::printf("| scene | blocks | S | serial error (m) | colored | block | jacobi |\n|---|---|---|---|---|---|---|\n");
  for (Case& c : cases) {
    const Eigen::Matrix3Xd converged = solved(c.world, Solver::serial, quick ? 1000 : 4000);
    W probe = c.world;
    StepParams<double> pb = probe.params();
    pb.solver = Solver::block;
    probe.set_params(pb);
    const Index blocks = (probe.num_colors(), probe.num_blocks());
    for (int s : {16, 64}) {
      const double target = rms_distance(solved(c.world, Solver::serial, s), converged);
      std::printf("| %s | %u | %d | %.3e |", c.name, unsigned(blocks), s, target);
      for (Solver solver : solvers) {
        const int limit = 8 * s;
        const int n = smallest(limit, [&](int k) { return rms_distance(solved(c.world, solver, k), converged) <= target; });
        std::printf(" %s |", ratio(n, s, limit).c_str());
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  // Chebyshev: sweeps to 1e-3 RMS relative stretch on the perturbed cloth, ρ estimated by a plain 64-sweep step.
  std::printf("\n## Sweeps to 1e-3 RMS relative stretch on the perturbed cloth, without and with Chebyshev\n\n");
  std::printf("| solver | ρ (estimated) | plain | Chebyshev | gain |\n|---|---|---|---|---|\n");
  const W& w = cases.front().world;
  const int limit = quick ? 1024 : 4096;
  for (Solver solver : solvers) {
    const double rho = stepped(w, solver, 64, 0.0).last_step_stats().chebyshev_rho;  // a plain step that estimates ρ
    auto stretch_after = [&](int k, double r) { return stretch_violation(stepped(w, solver, k, r)).rms; };
    const int plain = smallest(limit, [&](int k) { return stretch_after(k, -1) <= 1e-3; });
    const int fast = smallest(limit, [&](int k) { return k >= 2 && stretch_after(k, rho) <= 1e-3; });
    std::printf("| %s | %.4f | %s | %s | %s |\n", std::string(name(solver)).c_str(), rho,
                plain > limit ? ("> " + std::to_string(limit)).c_str() : std::to_string(plain).c_str(),
                fast > limit ? ("> " + std::to_string(limit)).c_str() : std::to_string(fast).c_str(),
                plain > limit || fast > limit ? "?" : (std::to_string(double(plain) / fast).substr(0, 4) + "×").c_str());
    std::fflush(stdout);
  }
  return 0;
}
