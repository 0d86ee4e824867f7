// Collision constraints and their continuous generation against planes and spheres.
#include "constraint_checks.hpp"
#include "contact/colliders.hpp"  // engine internal: the chunked generation
#include "pbd/colliders.hpp"

#include <oneapi/tbb/task_arena.h>

#include <cstring>

namespace pbd {
namespace {

TEST(Collision, SatisfiedInequalityMovesNothing) {
  double p[3] = {0.3, -0.2, 0.0};  // exactly on the plane z = 0 counts as satisfied
  const double w[1] = {1};
  double lambda = 0;
  const CollisionConstraint<double> c{{0}, {0, 0, 1}, 0.0};
  project(c, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_EQ(p[2], 0.0);
  p[2] = 0.25;
  project(c, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_EQ(p[2], 0.25);
  EXPECT_EQ(lambda, 0.0);
}

TEST(Collision, ViolatedInequalityProjectsOntoTheSurface) {
  double p[3] = {0.3, -0.2, -0.4};
  const double w[1] = {3};
  double lambda = 0;
  project(CollisionConstraint<double>{{0}, {0, 0, 1}, 0.1}, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_NEAR(p[2], 0.1, 1e-12);
  EXPECT_EQ(p[0], 0.3);
}

TEST(Collision, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3<double> p[1] = {test::random_point<double>(rng)};
    EXPECT_TRUE(test::check_gradient(
        CollisionConstraint<double>{{0}, test::random_point<double>(rng).normalized(), 0.2}, p));
  }
}

struct Path {
  Matrix3X<double> x, p;
  VectorX<double> w;
  Matrix3X<double> v = Matrix3X<double>::Zero(3, 1);
};
Path one_particle(Vec3<double> from, Vec3<double> to, double w = 1.0) {
  Path s{Matrix3X<double>(3, 1), Matrix3X<double>(3, 1), VectorX<double>::Constant(1, w)};
  s.x.col(0) = from;
  s.p.col(0) = to;
  return s;
}

TEST(CollisionGeneration, PlaneCatchesAPathEndingBehindIt) {
  Colliders<double> c;
  c.planes.push_back({{0, 0, 1}, 0});
  std::vector<CollisionConstraint<double>> out;
  auto s = one_particle({0, 0, 1}, {0, 0, -100});
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].offset, 0.0);
  s = one_particle({0, 0, 1}, {0, 0, 0.5});
  out.clear();
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  EXPECT_TRUE(out.empty());
}

TEST(CollisionGeneration, SpherePathThatTunnelsThroughIsCaughtAtItsEntry) {
  Colliders<double> c;
  c.spheres.push_back({{0, 0, 0}, 0.1});
  // Starts above, ends far below: both ends outside the ball, the path crosses it.
  auto s = one_particle({0, 0, 1}, {0, 0, -1});
  std::vector<CollisionConstraint<double>> out;
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].normal.z(), 1.0, 1e-12);
  EXPECT_NEAR(out[0].offset, 0.1, 1e-12);  // tangent plane at the top of the ball
}

TEST(CollisionGeneration, SphereMissIsIgnoredAndInsideIsPushedOut) {
  Colliders<double> c;
  c.spheres.push_back({{0, 0, 0}, 0.1});
  auto s = one_particle({1, 0, 1}, {1, 0, -1});  // passes beside the ball
  std::vector<CollisionConstraint<double>> out;
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  EXPECT_TRUE(out.empty());
  s = one_particle({0.05, 0, 0}, {0.06, 0, 0});  // starts inside: out along the radius through p
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].normal.x(), 1.0, 1e-12);
  EXPECT_NEAR(out[0].offset, 0.1, 1e-12);
  out.clear();
  s = one_particle({0, 0, 0}, {0, 0, 0});  // at the centre: a defined direction (+z), no NaN
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].normal.allFinite());
  EXPECT_NEAR(out[0].normal.norm(), 1.0, 1e-12);
}

TEST(CollisionGeneration, MarginAddsIdleContactsForParticlesEndingNear) {
  Colliders<double> c;
  c.planes.push_back({{0, 0, 1}, 0});
  c.spheres.push_back({{0, 0, 5}, 1});
  auto s = one_particle({0, 0, 2.5}, {0, 0, 0.05});  // ends 0.05 above the plane, far from the ball
  std::vector<CollisionConstraint<double>> out;
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  EXPECT_TRUE(out.empty());
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.1, {}, out);
  ASSERT_EQ(out.size(), 1u);  // the plane only: the sphere is far
  double p[3] = {0, 0, 0.05};
  const double w[1] = {1};
  double lambda = 0;
  project(out[0], p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_EQ(p[2], 0.05) << "a speculative contact is idle while it holds";
  s = one_particle({0, 0, 6.2}, {0, 0.5, 5.9});  // ends 0.03 outside the ball, never entering it
  out.clear();
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.1, {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].normal.norm(), 1.0, 1e-12);
  EXPECT_GT(out[0].normal.dot(s.p.col(0)) - out[0].offset, 0.0);
}

TEST(CollisionGeneration, PinnedParticlesNeverCollide) {
  Colliders<double> c;
  c.planes.push_back({{0, 0, 1}, 0});
  auto s = one_particle({0, 0, -1}, {0, 0, -1}, 0.0);
  std::vector<CollisionConstraint<double>> out;
  generate_collisions(c, s.x, s.p, s.v, s.w, 0.0, {}, out);
  EXPECT_TRUE(out.empty());
}

// The chunked generation (engine/src/contact/colliders.hpp) gives the serial list bit for bit on any thread count, and
// each contact's material is its collider's mixed with its particle's (the mixes are kept while a particle's material
// repeats): a cloud of 5000 particles of mixed radii and materials (in runs, as bodies have them), some pinned, about
// ten colliders (more than the mixes kept for), whose paths enter, end near, or miss them.
TEST(CollisionGeneration, ChunksGiveTheSerialListOnAnyThreadCount) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Index n = 5000;
  Matrix3X<float> x(3, n), p(3, n), v(3, n);
  VectorX<float> w(n), radius(n);
  std::vector<ContactMaterial<float>> material(n);
  const ContactMaterial<float> kinds[3] = {{0.5f, 0.4f, 0.1f}, {0.9f, 0.3f, 0.6f}, {0.2f, 0.2f, 0.0f}};
  for (Index i = 0; i < n; ++i) {
    x.col(i) = Vec3<float>(u(rng), u(rng), u(rng));
    p.col(i) = x.col(i) + 0.3f * Vec3<float>(u(rng), u(rng), u(rng));
    v.col(i) = 60.0f * (p.col(i) - x.col(i));
    w[i] = i % 17 == 0 ? 0.0f : 1.0f;
    radius[i] = i % 3 == 0 ? 0.0f : 0.02f;
    material[i] = kinds[(i / 37) % 3];
  }
  Colliders<float> c;
  for (int k = 0; k < 6; ++k) {
    const Vec3<float> nrm = Vec3<float>(u(rng), u(rng), u(rng)).normalized();
    c.planes.push_back({nrm, -0.5f, {0.1f * float(k + 1), 0.05f * float(k + 1), 0.1f * float(k)}});
  }
  for (int k = 0; k < 4; ++k)
    c.spheres.push_back({Vec3<float>(u(rng), u(rng), u(rng)), 0.3f, {0.3f + 0.1f * float(k), 0.2f, 0.05f * float(k)}});
  const ParticleSurfaces<float> surfaces{radius.data(), material.data()};
  std::vector<CollisionConstraint<float>> serial;
  generate_collisions(c, x, p, v, w, 0.01f, surfaces, serial);
  ASSERT_GT(serial.size(), std::size_t(n) / 2);
  for (const auto& k : serial) {
    const Index i = k.particles[0];
    bool from_a_collider = false;  // a plane's contact has its normal, bit for bit; a sphere's one of their mixes
    for (const auto& pl : c.planes)
      if (k.normal == pl.normal) {
        const ContactMaterial<float> mixed = mix_materials(pl.material, material[i]);
        from_a_collider = std::memcmp(&k.material, &mixed, sizeof mixed) == 0;
      }
    if (!from_a_collider)
      for (const auto& s : c.spheres) {
        const ContactMaterial<float> mixed = mix_materials(s.material, material[i]);
        from_a_collider = from_a_collider || std::memcmp(&k.material, &mixed, sizeof mixed) == 0;
      }
    EXPECT_TRUE(from_a_collider) << "particle " << i;
  }
  detail::CollisionChunks<float> chunks;
  for (int threads : {1, 2, 3}) {
    std::vector<CollisionConstraint<float>> chunked;
    tbb::task_arena(threads).execute(
        [&] { detail::generate_collisions_chunked(c, x, p, v, w, 0.01f, surfaces, true, chunks, chunked); });
    ASSERT_EQ(chunked.size(), serial.size()) << threads << " threads";
    EXPECT_EQ(std::memcmp(chunked.data(), serial.data(), serial.size() * sizeof serial[0]), 0) << threads << " threads";
  }
}

}  // namespace
}  // namespace pbd
