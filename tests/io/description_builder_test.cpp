// DescriptionBuilder and World<double> side by side: the same calls give the same description bit for bit (rest
// values, inverse masses, unit plane normals) and the same bad calls the same error message, adding nothing.
#include "error_checks.hpp"
#include "pbd/io/description_builder.hpp"
#include "pbd/io/describe_world.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace pbd {
namespace {

// Expects two contact materials to be equal, coefficient by coefficient.
void expect_same_material(const ContactMaterial<double>& a, const ContactMaterial<double>& b, const std::string& what) {
  EXPECT_EQ(a.static_friction, b.static_friction) << what;
  EXPECT_EQ(a.kinetic_friction, b.kinetic_friction) << what;
  EXPECT_EQ(a.restitution, b.restitution) << what;
}

// Expects `a` and `b` to hold the same values, each compared exactly.
void expect_same(const WorldDescription& a, const WorldDescription& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.velocities, b.velocities);
  EXPECT_EQ(a.inverse_masses, b.inverse_masses);
  ASSERT_EQ(a.sets.size(), b.sets.size());
  for (std::size_t i = 0; i < a.sets.size(); ++i) {
    EXPECT_EQ(a.sets[i].mode, b.sets[i].mode) << "set " << i;
    EXPECT_EQ(a.sets[i].k, b.sets[i].k) << "set " << i;
    EXPECT_EQ(a.sets[i].compliance, b.sets[i].compliance) << "set " << i;
  }
  // Every built-in type (the list): the same particles, set and rest values, bit for bit.
  for_each_type<BuiltinConstraintTypes<double>>([&](auto type, auto) {
    using C = typename decltype(type)::type;
    const auto& x = a.constraints<C>();
    const auto& y = b.constraints<C>();
    ASSERT_EQ(x.size(), y.size()) << C::kName;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_EQ(x[i].particles, y[i].particles) << C::kName << " " << i;
      EXPECT_EQ(x[i].set, y[i].set) << C::kName << " " << i;
      for_each_field<C>([&](const auto& field, auto) { EXPECT_EQ(x[i].*field.member, y[i].*field.member) << C::kName << " " << i; });
    }
  });
  ASSERT_EQ(a.volumes.size(), b.volumes.size());
  for (std::size_t i = 0; i < a.volumes.size(); ++i) {
    EXPECT_EQ(a.volumes[i].triangles, b.volumes[i].triangles) << "volume " << i;
    EXPECT_EQ(a.volumes[i].set, b.volumes[i].set) << "volume " << i;
    EXPECT_EQ(a.volumes[i].rest, b.volumes[i].rest) << "volume " << i;
    EXPECT_EQ(a.volumes[i].pressure.to, b.volumes[i].pressure.to) << "volume " << i;
  }
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t i = 0; i < a.planes.size(); ++i) {
    EXPECT_EQ(a.planes[i].normal, b.planes[i].normal) << "plane " << i;
    EXPECT_EQ(a.planes[i].offset, b.planes[i].offset) << "plane " << i;
    expect_same_material(a.planes[i].material, b.planes[i].material, "plane " + std::to_string(i));
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    EXPECT_EQ(a.spheres[i].center, b.spheres[i].center) << "sphere " << i;
    EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius) << "sphere " << i;
    expect_same_material(a.spheres[i].material, b.spheres[i].material, "sphere " + std::to_string(i));
  }
  ASSERT_EQ(a.contact_bodies.size(), b.contact_bodies.size());
  for (std::size_t i = 0; i < a.contact_bodies.size(); ++i) {
    const std::string what = "contact body " + std::to_string(i);
    EXPECT_EQ(a.contact_bodies[i].first, b.contact_bodies[i].first) << what;
    EXPECT_EQ(a.contact_bodies[i].count, b.contact_bodies[i].count) << what;
    EXPECT_EQ(a.contact_bodies[i].radius, b.contact_bodies[i].radius) << what;
    EXPECT_EQ(a.contact_bodies[i].self_collision, b.contact_bodies[i].self_collision) << what;
    expect_same_material(a.contact_bodies[i].material, b.contact_bodies[i].material, what);
  }
  EXPECT_EQ(a.params.dt, b.params.dt);
  EXPECT_EQ(a.params.gravity, b.params.gravity);
  EXPECT_EQ(a.params.substeps, b.params.substeps);
}

// Every kind of call, on a World<double> or a DescriptionBuilder.
template <class Target> void build_everything(Target& w) {
  ClothOptions cloth;
  cloth.resolution = 9;
  cloth.origin = {0.1, -0.3, 1.7};
  const Body c = add_cloth(w, cloth, w.add_constraint_set(Stiffness::pbd_k(0.9)));
  MeshConstraintSets surface;
  surface.bending = w.add_constraint_set(Stiffness::pbd_k(0.1));
  surface.area = w.add_constraint_set(Stiffness::xpbd_compliance(1e-6));
  add_mesh_constraints(w, c.triangles, surface);
  RopeOptions rope;
  rope.particles = 12;
  rope.direction = {1.0, 2.0, -0.5};
  rope.end_mass = 1000.0;
  const Body r = add_rope(w, rope, w.add_constraint_set(Stiffness::iteration_independent(0.5)));
  w.add_contact_body({c.first_particle, c.num_particles, 0.02, {0.6, 0.4, 0.1}, true});
  w.add_contact_body({r.first_particle, r.num_particles, 0.0, {}, false});
  MeshConstraintSets all;
  all.stretch = w.add_constraint_set(Stiffness::pbd_k(1.0));
  all.bending = w.add_constraint_set(Stiffness::pbd_k(0.3));
  all.area = w.add_constraint_set(Stiffness::pbd_k(0.7));
  all.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  all.pressure = {1.0, 2.5, 3.0};
  MeshBodyOptions body;
  body.scale = 0.37;
  body.origin = {0.3, 0.2, 2.9};
  body.mass = 3.3;
  body.pinned = {0, 5};
  add_mesh(w, icosphere_mesh(2, 0.61), body, all);
  add_mesh(w, dodecahedron_mesh(0.4), {}, all);
  add_mesh(w, tube_mesh(7, 4, 0.2, 1.3, true), body, all);
  Matrix3X<double> x(3, 3);
  x << 0.1, 0.7, 1.3, 0.2, -0.4, 0.9, 3.0, 3.1, 2.9;
  const Index first = w.add_particles(x, Eigen::Vector3d(0.3, 7.0, Target::kPinned));
  w.velocities().col(first + 1) = Vec3<double>(0.5, -1.5, 2.0);
  const Index s = w.add_constraint_set(Stiffness::pbd_k(0.2));
  w.add_stretch(first, first + 1, s);
  w.add_stretch(first + 1, first + 2, s, 0.25);
  w.add_anchor(first, s);
  w.add_anchor(first + 1, s, Vec3<double>(1, 2, 3));
  w.add_bending(0, 1, 10, 9, s, 2.5);
  w.add_area(0, 1, 10, s, 0.125);
  w.add_plane({0.3, -0.2, 1.1}, 0.7);
  w.add_plane({0, 0, 2}, -1, {0.8, 0.5, 0.25});
  w.add_sphere({0.5, 0.5, 0.2}, 0.3);
  w.add_sphere({-0.5, 0.5, 0.2}, 0.1, {0.0, 1e3, 1.0});
  StepParams<double> p;
  p.dt = 1.0 / 240;
  p.substeps = 3;
  p.gravity = {0.1, 0, -9.81};
  p.damping = 0.2;
  w.set_params(p);
}

TEST(DescriptionBuilder, TheSameCallsGiveWorldDoublesValuesBitForBit) {
  World<double> world;
  DescriptionBuilder builder;
  build_everything(world);
  build_everything(builder);
  expect_same(builder.description(), describe_world(world));
}

// Runs `call` on a built World<double> and a built DescriptionBuilder and expects the same error message from both,
// and neither changed.
void expect_same_error(const std::function<void(World<double>&)>& on_world,
                       const std::function<void(DescriptionBuilder&)>& on_builder) {
  World<double> world;
  DescriptionBuilder builder;
  build_everything(world);
  build_everything(builder);
  const std::string a = test::error_of([&] { on_world(world); });
  const std::string b = test::error_of([&] { on_builder(builder); });
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  expect_same(builder.description(), describe_world(world));
}

// The same call written once for both: `f` is a generic lambda taking the world or the builder.
template <class F> void expect_same_error(F f) {
  expect_same_error([&](World<double>& w) { f(w); }, [&](DescriptionBuilder& w) { f(w); });
}

TEST(DescriptionBuilder, TheSameBadCallsGiveWorldDoublesErrors) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  expect_same_error([](auto& w) { w.add_stretch(0, 1, 99); });
  expect_same_error([](auto& w) { w.add_stretch(0, 100000, 0); });
  expect_same_error([](auto& w) { w.add_stretch(3, 3, 0); });
  expect_same_error([&](auto& w) { w.add_stretch(0, 1, 0, -1.0); });
  expect_same_error([&](auto& w) { w.add_stretch(0, 1, 0, inf); });
  expect_same_error([&](auto& w) { w.add_anchor(0, 0, Vec3<double>(nan, 0, 0)); });
  expect_same_error([](auto& w) { w.add_anchor(999999, 0); });
  expect_same_error([](auto& w) { w.add_bending(0, 1, 2, 2, 0); });
  expect_same_error([](auto& w) { w.add_bending(0, 1, 2, 3, 0); });  // collinear grid row: degenerate
  expect_same_error([](auto& w) { w.add_bending(0, 1, 10, 9, 0, 4.0); });
  expect_same_error([&](auto& w) { w.add_bending(0, 1, 10, 9, 0, nan); });
  expect_same_error([](auto& w) { w.add_area(0, 1, 1, 0); });
  expect_same_error([&](auto& w) { w.add_area(0, 1, 10, 0, -2.0); });
  expect_same_error([](auto& w) {
    const std::vector<std::array<Index, 3>> open = {{0, 1, 10}};
    w.add_volume(open, 0);
  });
  expect_same_error([](auto& w) {  // a closed tetrahedron wound inside out
    Matrix3X<double> x = Matrix3X<double>::Zero(3, 4);
    x(0, 1) = x(1, 2) = x(2, 3) = 1.0;
    const Index f = w.add_particles(x, Eigen::Vector4d::Ones());
    const std::vector<std::array<Index, 3>> t = {{f, f + 1, f + 2}, {f, f + 3, f + 1}, {f, f + 2, f + 3},
                                                 {f + 1, f + 3, f + 2}};
    w.add_volume(t, 0);
  });
  expect_same_error([](auto& w) {  // a flat closed mesh: two triangles back to back
    const std::vector<std::array<Index, 3>> t = {{0, 1, 9}, {0, 9, 1}};
    w.add_volume(t, 0);
  });
  expect_same_error([](auto& w) {
    const std::vector<std::array<Index, 3>> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    w.add_volume(t, 0, PressureSchedule{0.0, 1.0, 0.0});
  });
  expect_same_error([&](auto& w) {
    Matrix3X<double> x = Matrix3X<double>::Zero(3, 2);
    x(1, 1) = inf;
    w.add_particles(x, Eigen::Vector2d(1, 1));
  });
  expect_same_error([](auto& w) { w.add_particles(Matrix3X<double>::Zero(3, 2), Eigen::Vector2d(1, -1)); });
  expect_same_error([](auto& w) { w.add_particles(Matrix3X<double>::Zero(3, 2), Eigen::Vector3d(1, 1, 1)); });
  expect_same_error([](auto& w) { w.add_constraint_set(Stiffness::pbd_k(1.5)); });
  expect_same_error([](auto& w) { w.add_constraint_set(Stiffness::xpbd_compliance(-1.0)); });
  expect_same_error([](auto& w) { w.add_plane({0, 0, 0}, 1.0); });
  expect_same_error([&](auto& w) { w.add_plane({0, 0, 1}, inf); });
  expect_same_error([](auto& w) { w.add_sphere({0, 0, 0}, 0.0); });
  expect_same_error([&](auto& w) { w.add_sphere({nan, 0, 0}, 1.0); });
  expect_same_error([](auto& w) { w.add_plane({0, 0, 1}, 0.0, {-0.1, 0.0, 0.0}); });
  expect_same_error([&](auto& w) { w.add_plane({0, 0, 1}, 0.0, {0.0, nan, 0.0}); });
  expect_same_error([&](auto& w) { w.add_sphere({0, 0, 0}, 1.0, {inf, 0.0, 0.0}); });
  expect_same_error([](auto& w) { w.add_sphere({0, 0, 0}, 1.0, {0.0, 0.0, 1.5}); });
  expect_same_error([&](auto& w) { w.add_sphere({0, 0, 0}, 1.0, {0.0, 0.0, nan}); });
  expect_same_error([](auto& w) { w.add_contact_body({0, 0, 0.1, {}, false}); });           // empty
  expect_same_error([](auto& w) { w.add_contact_body({0, 1u << 30, 0.1, {}, false}); });    // past the end
  expect_same_error([](auto& w) { w.add_contact_body({0xffffffffu, 2, 0.1, {}, false}); });  // first + count wraps
  expect_same_error([](auto& w) { w.add_contact_body({90, 5, 0.1, {}, false}); });          // overlaps body 1 (rope)
  expect_same_error([&](auto& w) {
    const Index last = w.num_particles() - 1;  // the explicit particles: in no contact body yet
    w.add_contact_body({last, 1, -0.01, {}, false});
  });
  expect_same_error([&](auto& w) { w.add_contact_body({w.num_particles() - 1, 1, inf, {}, false}); });
  expect_same_error([&](auto& w) { w.add_contact_body({w.num_particles() - 1, 1, 0.0, {0.0, -2.0, 0.0}, false}); });
  expect_same_error([&](auto& w) { w.add_contact_body({w.num_particles() - 1, 1, 0.0, {0.0, 0.0, -0.5}, true}); });
  expect_same_error([](auto& w) {
    StepParams<double> p;
    p.dt = 0;
    w.set_params(p);
  });
  expect_same_error([](auto& w) {
    StepParams<double> p;
    p.jacobi_omega = 2;
    w.set_params(p);
  });
  expect_same_error([](auto& w) {
    ClothOptions c;
    add_cloth(w, c, Index(1000));
  });
  expect_same_error([](auto& w) {
    MeshConstraintSets sets;
    sets.volume = Index(0);
    add_mesh(w, grid_mesh(3, 1.0), {}, sets);  // open: refused before anything is added
  });
  // Chebyshev's checks: the builder runs the engine's own set_params checks (pbd/checks.hpp), not a copy of them.
  for (auto bad : {+[](StepParams<double>& p) { p.chebyshev.rho = 1.5; },
                   +[](StepParams<double>& p) { p.chebyshev.max_rho = 1.0; },
                   +[](StepParams<double>& p) { p.chebyshev.delay = 0; },
                   +[](StepParams<double>& p) { p.iterations = 2; },  // rho 0 is estimated: needs 4 iterations
                   +[](StepParams<double>& p) { p.chebyshev.diverge = 1.0; },
                   +[](StepParams<double>& p) { p.solver = Solver::serial; }}) {
    expect_same_error([&](auto& w) {
      StepParams<double> p;
      p.chebyshev.enabled = true;
      bad(p);
      w.set_params(p);
    });
  }
  // Any built-in type's generic add<C> (the one Python and build_world call): the same checks and messages.
  expect_same_error([](auto& w) { w.add(StretchConstraint<double>{{0, 1}, 0, -1.0}); });
  expect_same_error([](auto& w) { w.add(AreaConstraint<double>{{0, 1, 1}, 0, 1.0}); });
  expect_same_error([](auto& w) { w.add(BendingConstraint<double>{{0, 1, 2, 3}, 0, 0.0}, 0); });  // degenerate
}

// The same bad value gives the same message through io (the builder scenes are read with) as through the API: a
// Chebyshev value, which io's own copy of the checks used to miss. (tests/new_type shows a bad rest value given in
// a scene and in a call.)
TEST(DescriptionBuilder, ASceneAndAnApiCallGiveTheSameMessage) {
  StepParams<double> p;
  p.chebyshev.enabled = true;
  p.chebyshev.rho = 1.5;
  World<double> world;
  DescriptionBuilder builder;
  const std::string api = test::error_of([&] { world.set_params(p); });
  const std::string io = test::error_of([&] { builder.set_params(p); });
  EXPECT_EQ(api, "set_params: chebyshev.rho must be in [0, 1) (0: estimated), got 1.5");
  EXPECT_EQ(api, io);
}

}  // namespace
}  // namespace pbd
