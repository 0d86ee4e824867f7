// Error measures: zero at rest, known values for known deformations, energy, reference distance, hash.
#include "pbd/io/build_world.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pbd {
namespace {

template <class Real> class MetricsTest : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(MetricsTest, Precisions);

const NamedViolation* find(const std::vector<NamedViolation>& v, const std::string& type) {
  for (const auto& t : v)
    if (t.type == type) return &t;
  return nullptr;
}

// A closed dodecahedron with stretch, bending, area and volume, plus an anchor and a ground plane below it.
template <class Real> World<Real> every_type() {
  World<double> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::pbd_k(1));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(1));
  sets.area = w.add_constraint_set(Stiffness::pbd_k(1));
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1));
  MeshBodyOptions opts;
  opts.origin = {0.0, 0.0, 1.0};
  add_mesh(w, dodecahedron_mesh(0.3), opts, sets);
  w.add_anchor(0, w.add_constraint_set(Stiffness::pbd_k(1)));
  w.add_plane({0, 0, 1}, 0.0);
  return build_world<Real>(describe_world(w));
}

TYPED_TEST(MetricsTest, EveryTypeIsZeroAtRest) {
  using Real = TypeParam;
  const World<Real> world = every_type<Real>();
  const auto v = constraint_violations(world);
  std::vector<std::string> types;
  for (const auto& t : v) types.push_back(t.type);
  EXPECT_EQ(types, (std::vector<std::string>{"stretch", "anchor", "bending", "area", "volume", "collision"}));
  const double tol = std::is_same_v<Real, float> ? 2e-6 : 1e-12;
  for (const auto& t : v) {
    EXPECT_GT(t.value.count, 0u) << t.type;
    EXPECT_LE(t.value.max, t.type == "bending" ? 100 * tol : tol) << t.type;  // acos near its kink amplifies rounding
  }
  EXPECT_EQ(find(v, "volume")->value.count, 1u);
  EXPECT_EQ(find(v, "collision")->value.count, std::size_t(world.num_particles()));  // one plane
  // Each type comes with the Measure its header declares: the study's error keys and units.
  std::vector<std::string> keys;
  for (const auto& t : v) keys.push_back(std::string(t.measure.key) + " " + t.measure.unit);
  EXPECT_EQ(keys, (std::vector<std::string>{"stretch_pct %", "anchor_mm mm", "bending_rad rad", "area_pct %",
                                            "volume_pct %", "penetration_mm mm"}));
  for (const auto& t : v) EXPECT_EQ(find_measure(t.type)->scale, t.measure.scale) << t.type;
  EXPECT_EQ(pooled(v).max, 0.0 + std::max({v[0].value.max, v[1].value.max, v[2].value.max, v[3].value.max,
                                            v[4].value.max, v[5].value.max}));
}

TYPED_TEST(MetricsTest, KnownStretch) {
  using Real = TypeParam;
  World<Real> world;
  const Index set = world.add_constraint_set(Stiffness::pbd_k(1));
  world.add_particle({0, 0, 0}, 1);
  world.add_particle({1, 0, 0}, 1);
  world.add_particle({3, 0, 0}, 1);
  world.add_stretch(0, 1, set);  // rest 1
  world.add_stretch(1, 2, set);  // rest 2
  world.positions()(0, 2) = Real(3.5);  // second edge 2.5 long: relative stretch 0.25
  const Violation v = stretch_violation(world);
  EXPECT_EQ(v.count, 2u);
  EXPECT_NEAR(v.max, 0.25, 1e-7);
  EXPECT_NEAR(v.rms, std::sqrt(0.25 * 0.25 / 2), 1e-7);
  world.positions()(0, 2) = Real(2.0);  // compressed to 1: relative 0.5 either way
  EXPECT_NEAR(stretch_violation(world).max, 0.5, 1e-7);
}

TYPED_TEST(MetricsTest, KnownBendingAngleAndArea) {
  using Real = TypeParam;
  World<Real> world;
  const Index set = world.add_constraint_set(Stiffness::pbd_k(1));
  // Edge p0-p1 on the x axis, wings p2 (+y) and p3 (−y): flat, φ0 = π.
  world.add_particle({0, 0, 0}, 1);
  world.add_particle({1, 0, 0}, 1);
  world.add_particle({0.5, 1, 0}, 1);
  world.add_particle({0.5, -1, 0}, 1);
  world.add_bending(0, 1, 2, 3, set);
  world.add_area(0, 1, 2, set);  // rest area 0.5
  // Fold wing p3 up by 30°: φ = π − 30°.
  const double a = std::numbers::pi / 6;
  world.positions().col(3) = Vec3<Real>(Real(0.5), Real(-std::cos(a)), Real(std::sin(a)));
  // Stretch the first triangle to twice its height: area 1, relative error 1.
  world.positions()(1, 2) = Real(2);
  const auto v = constraint_violations(world);
  ASSERT_NE(find(v, "bending"), nullptr);
  EXPECT_NEAR(find(v, "bending")->value.max, a, 1e-5);
  EXPECT_NEAR(find(v, "area")->value.max, 1.0, 1e-6);
  EXPECT_EQ(find(v, "collision"), nullptr);  // no colliders: not measured
}

TYPED_TEST(MetricsTest, KnownPenetrationVolumeAndAnchor) {
  using Real = TypeParam;
  World<Real> world = every_type<Real>();
  // Push particle 5 0.2 m below the ground and scale the whole mesh by 2 (volume × 8: relative error 7).
  const auto x0 = Matrix3X<Real>(world.positions());
  const Vec3<Real> c(0, 0, 1);
  for (Index i = 0; i < world.num_particles(); ++i) world.positions().col(i) = c + Real(2) * (x0.col(i) - c);
  const auto v = constraint_violations(world);
  EXPECT_NEAR(find(v, "volume")->value.max, 7.0, 1e-4);
  EXPECT_NEAR(find(v, "stretch")->value.max, 1.0, 1e-5);
  EXPECT_NEAR(find(v, "stretch")->value.rms, 1.0, 1e-5);  // every edge twice its rest length
  EXPECT_NEAR(find(v, "area")->value.rms, 3.0, 1e-5);     // every triangle four times its rest area
  EXPECT_NEAR(find(v, "anchor")->value.max, (x0.col(0) - c).template cast<double>().norm(), 1e-5);
  world.positions().col(5) = Vec3<Real>(0, 0, Real(-0.2));
  EXPECT_NEAR(penetration(world).max, 0.2, 1e-6);
  EXPECT_NEAR(penetration(world).rms, 0.2 / std::sqrt(double(world.num_particles())), 1e-6);  // 1 of 32 below
}

TYPED_TEST(MetricsTest, VolumeTargetFollowsThePressureSchedule) {
  using Real = TypeParam;
  World<double> w;
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1));
  sets.pressure = {1.0, 2.0, 0.0};  // target 2 × rest at once
  add_mesh(w, icosphere_mesh(1, 0.5), MeshBodyOptions{}, sets);
  const World<Real> world = build_world<Real>(describe_world(w));
  EXPECT_NEAR(volume_violation(world).max, 0.5, 1e-6);  // |V − 2V| / 2V
}

TYPED_TEST(MetricsTest, EnergyOfAFallingParticle) {
  using Real = TypeParam;
  World<Real> world;
  world.add_particle({0, 0, 2}, 3, {1, 0, 0});
  world.add_particle({0, 0, 5}, World<Real>::kPinned);  // pinned: no energy
  const Energy e = energy(world);
  EXPECT_NEAR(e.kinetic, 0.5 * 3 * 1, 1e-6);
  EXPECT_NEAR(e.potential, 3 * 9.81 * 2, 1e-4);
  EXPECT_NEAR(movable_mass(world), 3.0, 1e-6);
  // Free fall: the step is symplectic Euler (v += h g, then x += h v), which falls g h t / 2 further than the exact
  // parabola after time t, so the energy drifts by exactly −m g² h t / 2 (−2.406 J here).
  for (int i = 0; i < 60; ++i) world.step();
  const double g = 9.81, h = 1.0 / 60, t = 1.0;
  EXPECT_NEAR(energy(world).total() - e.total(), -3 * g * g * h * t / 2, 1e-3);
}

TYPED_TEST(MetricsTest, DistanceToReferenceAndBoundingDiagonal) {
  using Real = TypeParam;
  World<Real> world;
  world.add_particle({0, 0, 0}, 1);
  world.add_particle({3, 4, 0}, 1);
  EXPECT_NEAR(bounding_diagonal(world), 5.0, 1e-6);
  Matrix3X<double> ref(3, 2);
  ref << 0, 3, 0, 4, 0, 1;  // second particle 1 m off
  const Violation d = position_distance(world, ref);
  EXPECT_NEAR(d.max, 1.0, 1e-6);
  EXPECT_NEAR(d.rms, std::sqrt(0.5), 1e-6);
  EXPECT_THROW(position_distance(world, Matrix3X<double>(3, 3)), Error);
}

TYPED_TEST(MetricsTest, HashIsBitwise) {
  using Real = TypeParam;
  World<Real> a;
  a.add_particle({0, 0, 1}, 1);
  a.add_particle({1, 0, 1}, 1);
  World<Real> b = a;
  EXPECT_EQ(position_hash(a), position_hash(b));
  b.positions()(2, 1) = std::nextafter(Real(1), Real(2));  // one ulp
  EXPECT_NE(position_hash(a), position_hash(b));
  World<Real> empty;
  EXPECT_EQ(position_hash(empty), 0xcbf29ce484222325ull);  // FNV-1a of nothing is its offset basis
}

}  // namespace
}  // namespace pbd
