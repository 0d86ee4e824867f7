// Hierarchical PBD (engine/src/solve/hierarchy.hpp): the coarsening's invariants on cloths, ropes and meshes; the
// same bits on 1–4 threads, with contacts too; and physics against closed forms for every solver, with and without
// the hierarchy. Each physics check prints one greppable line
//   HIERARCHY check=<name> solver=<...> real=<float|double> hierarchy=<0|1> ... error=<relative>
#include "solve/hierarchy.hpp"

#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "hanging_chain.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace pbd {
namespace {

using test::run_on;

template <class Real> class HierarchyTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(HierarchyTest, Precisions);

template <class Real> const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

template <class Real> World<Real> cloth(int n, Stiffness stretch, bool bending) {
  World<Real> w;
  const Index set = w.add_constraint_set(stretch);
  ClothOptions o;
  o.resolution = n;
  const Body b = add_cloth(w, o, set);
  if (bending) {
    MeshConstraintSets sets;
    sets.bending = w.add_constraint_set(Stiffness::xpbd_compliance(1.0));
    add_mesh_constraints(w, b.triangles, sets);
  }
  return w;
}

template <class Real> void expect_valid(const World<Real>& w, Hierarchy settings, std::size_t min_levels) {
  const detail::HierarchyModel<Real> h = detail::build_hierarchy(w.model(), settings);
  const Matrix3X<Real> x = w.positions();
  EXPECT_EQ(detail::validate_hierarchy(h, w.model(), &x), "");
  EXPECT_GE(h.levels.size(), min_levels);
  for (std::size_t l = 1; l < h.levels.size(); ++l) EXPECT_LT(h.levels[l].particles.size(), h.levels[l - 1].particles.size());
}

TYPED_TEST(HierarchyTest, CoarseningKeepsItsInvariantsOnClothsRopesAndMeshes) {
  using Real = TypeParam;
  for (int k : {1, 2, 3}) {
    Hierarchy s;
    s.enabled = true;
    s.parents = k;
    s.levels = 6;
    s.compliant = true;  // the ropes' sets are compliant
    expect_valid(cloth<Real>(23, Stiffness::pbd_k(1), false), s, 3);
    World<Real> rope;
    RopeOptions ro;
    ro.particles = 31;
    add_rope(rope, ro, rope.add_constraint_set(Stiffness::xpbd_compliance(1e-3)));
    expect_valid(rope, s, k <= 2 ? 2 : 0);  // with k = 3 no particle of a rope has enough neighbours to leave
    World<Real> ball;
    MeshConstraintSets sets;
    sets.stretch = ball.add_constraint_set(Stiffness::pbd_k(1));
    MeshBodyOptions mo;
    mo.pinned = {0};
    add_mesh(ball, icosphere_mesh(3, 0.5), mo, sets);
    expect_valid(ball, s, 2);
  }
  // A chain keeps every other particle: 31 → 16 → 8 (+ the end, promoted), the pinned top in every level, and a
  // coarse link carries the rest lengths (times 1 + slack) and compliances of the two links it spans.
  World<Real> chain;
  RopeOptions ro;
  ro.particles = 31;
  ro.length = 3.0;
  add_rope(chain, ro, chain.add_constraint_set(Stiffness::xpbd_compliance(1e-3)));
  Hierarchy s;
  s.levels = 2;
  s.compliant = true;
  const detail::HierarchyModel<Real> h = detail::build_hierarchy(chain.model(), s);
  ASSERT_EQ(h.levels.size(), 2u);
  EXPECT_EQ(h.levels[0].particles.size(), 16u);
  EXPECT_EQ(h.levels[0].particles.front(), 0u);
  EXPECT_NEAR(double(h.levels[0].rest[0]), 0.2 * (1 + s.slack), 1e-6);  // the path's, with the slack
  EXPECT_NEAR(double(h.levels[1].rest[0]), 0.4 * (1 + s.slack), 1e-6);  // not compounded level by level
  EXPECT_NEAR(double(h.levels[0].compliance[0]), 2e-3, 1e-9);
  EXPECT_EQ(h.levels[0].w[0][0] == Real(0) || h.levels[0].w[0][1] == Real(0), true);  // link 0–2: the pinned top
}

TYPED_TEST(HierarchyTest, SameBitsOnOneToFourThreadsWithAndWithoutContacts) {
  using Real = TypeParam;
  for (bool contacts : {false, true}) {
    World<Real> w = cloth<Real>(40, Stiffness::pbd_k(1), true);
    if (contacts) {
      w.add_sphere(Vec3<Real>(Real(0.5), Real(0.4), Real(0.6)), Real(0.25));
      w.add_contact_body({0, w.num_particles(), Real(0.008), {}, true});
    }
    for (Solver solver : kSolvers) {
      StepParams<Real> p = w.params();
      p.solver = solver;
      p.substeps = 4;
      p.iterations = 2;
      p.hierarchy.enabled = true;
      p.hierarchy.levels = 3;
      w.set_params(p);
      const std::uint64_t one = run_on(w, 1, 12);
      for (int threads : {2, 3, 4}) EXPECT_EQ(run_on(w, threads, 12), one) << name(solver) << " contacts " << contacts << " threads " << threads;
      // Every loop cut small, the coarse levels' too: the fork/join runner cuts each into many parts, and without
      // contacts a step may run on one thread team (when workers join in time), whose members split each loop.
      ParallelConfig shared;
      shared.inline_below = 16;
      shared.min_grain = 16;
      w.set_parallel_config(shared);
      for (int threads : {2, 4}) EXPECT_EQ(run_on(w, threads, 12), one) << name(solver) << " contacts " << contacts << " threads " << threads << ", every loop shared";
      w.set_parallel_config(ParallelConfig{});
      p.hierarchy.enabled = false;
      w.set_params(p);
      EXPECT_NE(run_on(w, 1, 12), one) << name(solver) << ": the hierarchy changed nothing";
    }
  }
}

// A vertical compliant chain (30 links of 5 cm, 10 g particles, α = 1e-3) damped to rest: link k stretches by
// α·T_k, T_k the weight below it.
template <class Real> double chain_error(Solver s, Hierarchy h, int substeps, int iterations) {
  const int n = 30;
  const double m = 0.01, rest = 0.05, alpha = 1e-3, g = 9.81;
  double closed = 0;
  for (int k = 1; k <= n; ++k) closed += alpha * (n - k + 1) * m * g;
  World<Real> w = test::hanging_chain<Real>(n, m, rest, alpha, s);
  StepParams<Real> p = w.params();
  p.damping = Real(1);
  p.substeps = substeps;
  p.iterations = iterations;
  p.hierarchy = h;
  w.set_params(p);
  for (int step = 0; step < 600; ++step) w.step();  // 10 s: damped to rest
  w.validate();
  const double extension = -double(w.positions()(2, n)) - n * rest;
  return extension / closed - 1;
}

// The hierarchy leaves a compliant material as it is (it coarsens only α = 0 stretch unless told otherwise): the
// chain settles at α·T with it on, at the budget that converges without it. With `compliant` the coarse pass takes
// the chain too, and the line printed measures how far that moves the answer (solve/hierarchy.hpp's note).
TYPED_TEST(HierarchyTest, CompliantChainSettlesAtAlphaTimesTension) {
  using Real = TypeParam;
  Hierarchy on;
  on.enabled = true;
  Hierarchy compliant = on;
  compliant.compliant = true;
  for (Solver s : kSolvers) {
    const double off = chain_error<Real>(s, Hierarchy{}, 10, 10), with = chain_error<Real>(s, on, 10, 10);
    const double moved = chain_error<Real>(s, compliant, 10, 10), short_budget = chain_error<Real>(s, compliant, 1, 20);
    std::printf("HIERARCHY check=chain solver=%s real=%s split=10x10 error_off=%.4g error_on=%.4g "
                "error_compliant=%.4g error_compliant_1x20=%.4g\n", std::string(name(s)).c_str(), real_name<Real>(),
                off, with, moved, short_budget);
    EXPECT_LT(std::abs(off), 0.01) << name(s);
    EXPECT_LT(std::abs(with), 0.01) << name(s);
  }
}

// A cloth (k = 1 stretch, no bending) damped to rest: every edge at its rest length, whatever the solver.
TYPED_TEST(HierarchyTest, DampedClothComesToRestUnstretched) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
    for (bool hierarchy : {false, true}) {
      World<Real> w = cloth<Real>(12, Stiffness::pbd_k(1), false);
      StepParams<Real> p = w.params();
      p.solver = s;
      p.damping = Real(4);
      p.substeps = 8;
      p.iterations = s == Solver::jacobi ? 40 : 16;
      p.hierarchy.enabled = hierarchy;
      w.set_params(p);
      for (int step = 0; step < 300; ++step) w.step();
      const Violation v = stretch_violation(w);
      std::printf("HIERARCHY check=cloth-at-rest solver=%s real=%s hierarchy=%d rms=%.4g max=%.4g\n",
                  std::string(name(s)).c_str(), real_name<Real>(), int(hierarchy), v.rms, v.max);
      EXPECT_LT(v.rms, 1e-3) << name(s) << " hierarchy " << hierarchy;
    }
  }
}

TEST(HierarchyParams, SceneKeyRoundTripsAndBadSettingsAreErrors) {
  const std::string head = R"({"name": "h", "dt": 0.01, "bodies": [{"type": "rope", "particles": 5, "stretch": {}}], )";
  const Scene on = parse_scene(head + R"("hierarchy": {"levels": 3, "parents": 1, "sweeps": 2}})", "h.json");
  EXPECT_TRUE(on.world.params.hierarchy.enabled);
  EXPECT_EQ(on.world.params.hierarchy.levels, 3);
  const World<float> w = build_world<float>(on.world);
  EXPECT_EQ(w.params().hierarchy, on.world.params.hierarchy);
  EXPECT_EQ(describe_world(w).params.hierarchy, on.world.params.hierarchy);
  EXPECT_TRUE(parse_scene(head + R"("hierarchy": true})", "h.json").world.params.hierarchy.enabled);
  EXPECT_FALSE(parse_scene(head + R"("hierarchy": 0})", "h.json").world.params.hierarchy.enabled);
  EXPECT_EQ(parse_scene(head + R"("hierarchy": 2})", "h.json").world.params.hierarchy.levels, 2);
  EXPECT_THROW(parse_scene(head + R"("hierarchy": {"levels": 0}})", "h.json"), Error);
  EXPECT_THROW(parse_scene(head + R"("hierarchy": {"level": 2}})", "h.json"), Error);
  EXPECT_THROW(parse_scene(head + R"("hierarchy": "yes"})", "h.json"), Error);
  EXPECT_EQ(parse_scene(head + R"("hierarchy": {"slack": 0.002}})", "h.json").world.params.hierarchy.slack, 0.002);
  for (const char* slack : {"-0.001", "0.2"}) {
    try {
      parse_scene(head + R"("hierarchy": {"slack": )" + slack + "}}", "h.json");
      ADD_FAILURE() << "slack " << slack << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("slack"), std::string::npos) << e.what();
    }
  }
  World<double> bad;
  StepParams<double> p;
  p.hierarchy.parents = 0;
  try {
    bad.set_params(p);
    ADD_FAILURE() << "parents 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("hierarchy.parents"), std::string::npos) << e.what();
  }
  p.hierarchy.parents = 2;
  p.hierarchy.slack = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bad.set_params(p), Error);
  EXPECT_EQ(bad.params().hierarchy, Hierarchy{});
}

// A cloth damped to rest stays unstretched at many sub-steps, and the slack is what keeps it so: at slack 0 the pass
// corrects the sweeps' own residual every sub-step and the loop through the interpolation crumples the cloth
// (hierarchy.hpp; the figures: docs/performance.md, "A cloth at rest, and the slack").
TEST(HierarchyTest, ClothDampedToRestStaysUnstretchedAtManySubsteps) {
  auto rest_stretch = [](double slack, int substeps) {
    const std::string scene =
        R"({"name": "rest", "dt": 0.016666666666666666, "substeps": )" + std::to_string(substeps) +
        R"(, "iterations": 1, "damping": 6.0,
        "hierarchy": {"levels": 4, "slack": )" + std::to_string(slack) + R"(}, "bodies": [{"type": "cloth",
        "resolution": 20, "pin": "corners", "stretch": {"stiffness": 1.0}, "bending": {"compliance": 1000.0},
        "tethers": true}]})";
    World<double> w = build_world<double>(parse_scene(scene, "rest.json").world);
    for (int step = 0; step < 240; ++step) w.step();  // 4 s, damped to rest
    return stretch_violation(w).rms;
  };
  for (int substeps : {16, 128}) EXPECT_LT(rest_stretch(Hierarchy{}.slack, substeps), 1e-3) << substeps << " sub-steps";
  EXPECT_GT(rest_stretch(0.0, 128), 5e-3) << "slack 0 no longer crumples the cloth: revisit the slack (hierarchy.hpp)";
}

}  // namespace
}  // namespace pbd
