// The list of built-in constraint types (constraint_types.hpp) walked type by type: each type declares what the
// passes derived from the list need (constraints/traits.hpp), consistently, and each pass takes it. A type that
// lost a declaration, or two types that share a name or a key, fail here rather than silently in one pass.
#include "error_checks.hpp"
#include "pbd/checks.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace pbd {
namespace {

using Types = BuiltinConstraintTypes<double>;

bool named(const char* s) { return s != nullptr && s[0] != '\0'; }

TEST(ConstraintTypes, EachTypeDeclaresWhatThePassesNeedWithUniqueNamesAndKeys) {
  std::set<std::string> names, scene_keys, measures;
  for (const NamedMeasure& m : violation_measures()) EXPECT_TRUE(measures.insert(m.measure.key).second) << m.type;
  EXPECT_EQ(measures.size(), kNumBuiltinTypes + 3) << "the list's measures, volume, collision, particle contact";
  for_each_type<Types>([&](auto type, auto index) {
    using C = typename decltype(type)::type;
    SCOPED_TRACE(C::kName);
    EXPECT_TRUE(named(C::kName) && named(C::kNoun) && named(C::kSceneKey));
    EXPECT_TRUE(names.insert(C::kName).second) << "a second type named " << C::kName;
    EXPECT_TRUE(scene_keys.insert(C::kSceneKey).second) << "a second type with scene key " << C::kSceneKey;
    EXPECT_EQ((TypeIndex<C, Types>::value), decltype(index)::value);
    EXPECT_GE(C::kArity, 1);
    // Python's add_<name>: one distinct argument name per particle, none shadowing "set" or a rest value.
    std::set<std::string> args{"set"};
    for (const char* p : C::kParticleNames) EXPECT_TRUE(named(p) && args.insert(p).second) << p;
    for_each_field<C>([&](const auto& field, auto) {
      EXPECT_TRUE(named(field.name) && named(field.noun));
      EXPECT_TRUE(args.insert(field.name).second) << field.name;
    });
    // Its metrics: a Measure with a key, a label, a unit and a positive scale, found by its name.
    EXPECT_TRUE(named(C::kMeasure.key) && named(C::kMeasure.label) && named(C::kMeasure.unit));
    EXPECT_GT(C::kMeasure.scale, 0.0);
    const Measure* m = find_measure(C::kName);
    ASSERT_NE(m, nullptr);
    EXPECT_STREQ(m->key, C::kMeasure.key);
  });
}

// Eight particles in general position (no three on a line, no four in a plane), as many as the largest arity (a
// shape-matching cluster): every built-in type's constraint on the first kArity of them has a defined rest value
// (no degenerate triangle, a tet of positive volume, a cluster that spans space).
World<float> eight_particles() {
  World<float> w;
  w.add_particle({0, 0, 0}, 1.0f);
  w.add_particle({1, 0, 0}, 1.0f);
  w.add_particle({0.2f, 1, 0.1f}, 1.0f);
  w.add_particle({0.3f, -1, 0.4f}, 1.0f);
  w.add_particle({-0.6f, 0.4f, 0.9f}, 1.0f);
  w.add_particle({0.8f, 0.7f, -0.5f}, 1.0f);
  w.add_particle({-0.3f, -0.8f, -0.7f}, 1.0f);
  w.add_particle({1.1f, -0.4f, 1.2f}, 1.0f);
  w.add_constraint_set(Stiffness::pbd_k(1.0));
  return w;
}

// Each type through every pass outside the solver: the generic add (rest values measured), stepping with every
// solver, validate(), its violation with its Measure, the describe round trip, and removal.
TEST(ConstraintTypes, EachTypeGoesThroughEveryPass) {
  for_each_type<BuiltinConstraintTypes<float>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    SCOPED_TRACE(C::kName);
    for (Solver solver : kSolvers) {
      World<float> w = eight_particles();
      C c = blank_constraint<C>();
      for (int i = 0; i < C::kArity; ++i) c.particles[i] = Index(i);
      EXPECT_EQ(w.add(c, required_fields<C>()), 0u);  // blank values for what has no default
      ASSERT_EQ(w.template constraints<C>().size(), 1u);
      auto p = w.params();
      p.solver = solver;
      w.set_params(p);
      for (int s = 0; s < 3; ++s) w.step();
      w.validate();
      const auto violations = constraint_violations(w);
      ASSERT_EQ(violations.size(), 1u);
      EXPECT_EQ(violations[0].type, C::kName);
      EXPECT_STREQ(violations[0].measure.key, C::kMeasure.key);
      EXPECT_EQ(violations[0].value.count, 1u);
      const World<float> back = build_world<float>(describe_world(w));
      ASSERT_EQ(back.template constraints<C>().size(), 1u);
      EXPECT_EQ(back.template constraints<C>()[0].particles, w.template constraints<C>()[0].particles);
      const std::array<Index, 1> first{0};
      w.template remove_constraints<C>(first);
      EXPECT_TRUE(w.template constraints<C>().empty());
      EXPECT_EQ(test::error_of([&] { w.template remove_constraints<C>(first); }),
                std::string("remove_") + C::kName + ": constraint index 0 out of range (0 constraints)");
      w.validate();
    }
  });
}

// A bad constraint of each type names the call and the item: add_<name>: <noun> <index>: ...
TEST(ConstraintTypes, EachTypesChecksNameTheCallAndTheItem) {
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    World<double> w;
    w.add_particle({0, 0, 0}, 1.0);
    w.add_constraint_set(Stiffness::pbd_k(1.0));
    C c = blank_constraint<C>();
    c.particles[0] = 5;
    EXPECT_EQ(test::error_of([&] { w.add(c); }), std::string("add_") + C::kName + ": " + C::kNoun +
                                                     " 0: particle index 5 out of range (the world has 1 particles)");
  });
}

}  // namespace
}  // namespace pbd
