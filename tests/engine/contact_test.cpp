// Contacts against closed forms, for every solver (issue 24): friction on an incline, restitution of a drop and of
// a head-on pair, a falling pile whose spheres never overlap, and a cloth that never passes through itself.
// Each closed-form check prints one greppable line
//   CONTACT check=<name> solver=<...> real=<float|double> <measured>=<x> <closed form>=<y> error=<relative>
#include "pbd/world.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace pbd {
namespace {

template <class Real> class Contact : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Contact, Precisions);

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

template <class Real> const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

void print_line(const char* check, Solver s, const char* real, const char* what, double measured, const char* form,
                double expected) {
  std::printf("CONTACT check=%s solver=%s real=%s %s=%.6g %s=%.6g error=%.3g\n", check, std::string(name(s)).c_str(),
              real, what, measured, form, expected, std::abs(measured - expected) / std::abs(expected));
}

template <class Real> StepParams<Real> params(Solver s, int substeps, int iterations) {
  StepParams<Real> p;
  p.solver = s;
  p.substeps = substeps;
  p.iterations = iterations;
  p.gravity = Vec3<Real>(0, 0, Real(-kG));
  p.damping = 0;
  return p;
}

// One particle resting on a plane through the origin tilted by θ about y (downhill is +x), with friction μs, μk.
template <class Real> World<Real> incline(double theta, double mus, double muk, Solver s) {
  World<Real> w;
  w.add_particle(Vec3<Real>::Zero(), Real(1));
  const Vec3<Real> n(Real(std::sin(theta)), Real(0), Real(std::cos(theta)));
  w.add_plane(n, Real(0), ContactMaterial<Real>{Real(mus), Real(muk), Real(0)});
  w.set_params(params<Real>(s, 4, 4));
  return w;
}

// Distance travelled downhill (along the plane) by the incline's particle.
template <class Real> double downhill(const World<Real>& w, double theta) {
  const auto x = w.positions().col(0).template cast<double>();
  return x.x() * std::cos(theta) - x.z() * std::sin(theta);
}

TYPED_TEST(Contact, InclineHoldsWhenStaticFrictionExceedsTheSlope) {
  using Real = TypeParam;
  const double theta = 20 * kPi / 180;  // tan θ = 0.364
  for (Solver s : kSolvers) {
    World<Real> w = incline<Real>(theta, 0.4, 0.3, s);
    for (int i = 0; i < 120; ++i) w.step();
    EXPECT_LT(std::abs(downhill(w, theta)), 1e-5) << name(s);
    EXPECT_LT(w.velocities().col(0).norm(), Real(1e-4)) << name(s);
  }
}

TYPED_TEST(Contact, InclineSlidesWithKineticFriction) {
  using Real = TypeParam;
  const double theta = 30 * kPi / 180, muk = 0.3;  // μs = 0.5 < tan θ = 0.577
  const double a = kG * (std::sin(theta) - muk * std::cos(theta));
  for (Solver s : kSolvers) {
    World<Real> w = incline<Real>(theta, 0.5, muk, s);
    const int steps = 60;
    for (int i = 0; i < steps; ++i) w.step();
    const double t = steps / 60.0;  // from the velocity: the position carries Euler's (N + 1)/N offset
    const auto v = w.velocities().col(0).template cast<double>();
    const double measured = (v.x() * std::cos(theta) - v.z() * std::sin(theta)) / t;
    EXPECT_GT(downhill(w, theta), 0.0) << name(s);
    print_line("incline_slide", s, real_name<Real>(), "acceleration", measured, "g(sin-mu_k*cos)", a);
    EXPECT_NEAR(measured, a, 0.01 * a) << name(s);
  }
}

TYPED_TEST(Contact, DropReboundsToRestitutionSquaredTimesTheHeight) {
  using Real = TypeParam;
  const double h0 = 1.0, e = 0.6;
  for (Solver s : kSolvers) {
    World<Real> w;
    w.add_particle(Vec3<Real>(0, 0, Real(h0)), Real(1));
    w.add_plane(Vec3<Real>(0, 0, 1), Real(0), ContactMaterial<Real>{Real(0), Real(0), Real(e)});
    w.set_params(params<Real>(s, 20, 2));
    double peak = 0;
    bool bounced = false;
    for (int i = 0; i < 120; ++i) {
      const double vz_before = double(w.velocities()(2, 0));
      w.step();
      const double vz = double(w.velocities()(2, 0));
      if (vz > 0 && vz_before <= 0) bounced = true;
      if (bounced) peak = std::max(peak, double(w.positions()(2, 0)));
      if (bounced && vz < 0) break;
    }
    ASSERT_TRUE(bounced) << name(s);
    print_line("drop_rebound", s, real_name<Real>(), "height", peak, "e^2*h", e * e * h0);
    EXPECT_NEAR(peak, e * e * h0, 0.02 * e * e * h0) << name(s);
  }
}

TYPED_TEST(Contact, HeadOnPairKeepsMomentumAndSeparatesAtRestitutionTimesTheApproach) {
  using Real = TypeParam;
  const double e = 0.5, v0 = 2.0, m1 = 1.0, m2 = 3.0;
  for (Solver s : kSolvers) {
    World<Real> w;
    w.add_particle(Vec3<Real>(Real(-0.5), 0, 0), Real(m1), Vec3<Real>(Real(v0), 0, 0));
    w.add_particle(Vec3<Real>(Real(0.5), 0, 0), Real(m2), Vec3<Real>(Real(-v0), 0, 0));
    w.add_contact_body({0, 1, Real(0.1), {Real(0), Real(0), Real(e)}});
    w.add_contact_body({1, 1, Real(0.1), {Real(0), Real(0), Real(0)}});
    StepParams<Real> p = params<Real>(s, 8, 2);
    p.gravity.setZero();
    w.set_params(p);
    for (int i = 0; i < 30; ++i) w.step();
    const double u1 = double(w.velocities()(0, 0)), u2 = double(w.velocities()(0, 1));
    const double momentum = m1 * u1 + m2 * u2, before = m1 * v0 - m2 * v0;
    EXPECT_NEAR(momentum, before, 1e-4 * std::abs(before) + 1e-5) << name(s);
    print_line("pair_restitution", s, real_name<Real>(), "separation_speed", u2 - u1, "e*approach", e * 2 * v0);
    EXPECT_NEAR(u2 - u1, e * 2 * v0, 0.01 * e * 2 * v0) << name(s);
    EXPECT_GE(double(w.positions()(0, 1) - w.positions()(0, 0)), 0.2 * (1 - 1e-3)) << name(s);
  }
}

// A contact body's interior particles (ContactBody::interior: a tet body's inner ones) are points: a ball of another
// body flies through one untouched, where it bounces off the same particle when that particle is not interior, and
// the interior particle still lands on the ground (a collider) as a point.
TYPED_TEST(Contact, InteriorParticlesTouchCollidersButNoOtherParticle) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
    for (bool interior : {true, false}) {
      World<Real> w;
      w.add_particle(Vec3<Real>(Real(0), Real(3), Real(0.5)), Real(1));  // the body's surface, far away
      w.add_particle(Vec3<Real>(Real(0), Real(0), Real(0.5)), Real(1));  // its inner particle, in the ball's way
      w.add_particle(Vec3<Real>(Real(-0.5), Real(0), Real(0.5)), Real(1), Vec3<Real>(Real(4), 0, 0));
      ContactBody<Real> body{0, 2, Real(0.1)};
      if (interior) body.interior = {1};
      w.add_contact_body(body);
      w.add_contact_body({2, 1, Real(0.1)});
      w.add_plane(Vec3<Real>(0, 0, 1), Real(0));
      StepParams<Real> p = params<Real>(s, 8, 2);
      p.gravity = Vec3<Real>(0, 0, Real(-9.81));
      w.set_params(p);
      for (int i = 0; i < 60; ++i) w.step();  // 1 s: the ball passes x = 0 at 0.125 s, before anything lands
      const double ball_vx = double(w.velocities()(0, 2)), inner_x = double(w.positions()(0, 1));
      if (interior) {
        EXPECT_NEAR(ball_vx, 4.0, 1e-4) << name(s);  // untouched
        EXPECT_NEAR(inner_x, 0.0, 1e-6) << name(s);
        EXPECT_NEAR(double(w.positions()(2, 1)), 0.0, 1e-3) << name(s);  // a point on the ground
      } else {
        EXPECT_LT(ball_vx, 3.0) << name(s);  // the same particle, as a ball, takes momentum from it
        EXPECT_GT(inner_x, 0.5) << name(s);
      }
    }
  }
  World<Real> w;  // an interior particle outside the body's run, or out of order, is refused
  for (int i = 0; i < 3; ++i) w.add_particle(Vec3<Real>(Real(i), 0, 0), Real(1));
  ContactBody<Real> outside{0, 2, Real(0.1)};
  outside.interior = {2};
  EXPECT_THROW(w.add_contact_body(outside), Error);
  ContactBody<Real> unordered{0, 3, Real(0.1)};
  unordered.interior = {2, 1};
  EXPECT_THROW(w.add_contact_body(unordered), Error);
  EXPECT_TRUE(w.contact_bodies().empty());
}

TYPED_TEST(Contact, FastParticlesDoNotPassThroughEachOther) {
  using Real = TypeParam;
  for (Solver s : kSolvers) {
    World<Real> w;  // 100 m/s each, radii 0.01 m: each moves 1.7 m in a step of one sub-step
    w.add_particle(Vec3<Real>(Real(-1), 0, 0), Real(1), Vec3<Real>(Real(100), 0, 0));
    w.add_particle(Vec3<Real>(Real(1), 0, 0), Real(1), Vec3<Real>(Real(-100), 0, 0));
    w.add_contact_body({0, 1, Real(0.01)});
    w.add_contact_body({1, 1, Real(0.01)});
    StepParams<Real> p = params<Real>(s, 1, 4);
    p.gravity.setZero();
    w.set_params(p);
    for (int i = 0; i < 3; ++i) w.step();
    EXPECT_LT(w.positions()(0, 0), w.positions()(0, 1)) << name(s);
  }
}

// 1000 particles of radius r dropped into a box as a loose lattice (one self-colliding body: nothing joins them).
template <class Real> World<Real> pile(Solver s, double r, int side) {
  World<Real> w;
  std::uint32_t seed = 12345;
  auto jitter = [&] {  // deterministic, in [-0.1, 0.1] r
    seed = seed * 1664525u + 1013904223u;
    return (double(seed >> 8) / double(1u << 24) - 0.5) * 0.2 * r;
  };
  const double spacing = 2.3 * r, half = 0.5 * side * spacing + r;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        w.add_particle(Vec3<Real>(Real((i + 0.5) * spacing - 0.5 * side * spacing + jitter()),
                                  Real((j + 0.5) * spacing - 0.5 * side * spacing + jitter()),
                                  Real(r + 0.5 * spacing + k * spacing * 1.5 + jitter())),
                       Real(0.01));
  const ContactMaterial<Real> rough{Real(0.4), Real(0.3), Real(0)};
  w.add_contact_body({0, w.num_particles(), Real(r), rough, true});
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0), rough);
  w.add_plane(Vec3<Real>(1, 0, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(-1, 0, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(0, 1, 0), Real(-half), rough);
  w.add_plane(Vec3<Real>(0, -1, 0), Real(-half), rough);
  // Ten layers deep: the floor's support climbs the pile one contact per sweep, and the impacts of the upper layers
  // are the worst moments. 16 sub-steps of 5 sweeps keep every overlap under 1% (at 4 × 10: 1.3% serial, 2.5%
  // colored; at 8 × 10: 0.45% and 0.84%).
  StepParams<Real> p = params<Real>(s, 16, 5);
  p.collision_margin = Real(0.2 * r);
  w.set_params(p);
  return w;
}

// Largest overlap of any two particles' spheres, as a fraction of their radii sum (all pairs: a check independent
// of the engine's grid).
template <class Real> double worst_overlap(const World<Real>& w, double r) {
  const auto x = w.positions();
  std::vector<Index> order(w.num_particles());
  for (Index i = 0; i < w.num_particles(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return x(0, a) < x(0, b); });
  double worst = 0;
  for (std::size_t a = 0; a < order.size(); ++a)  // sweep along x: a pair closer than 2r is closer along x too
    for (std::size_t b = a + 1; b < order.size() && double(x(0, order[b]) - x(0, order[a])) < 2 * r; ++b) {
      const double d = (x.col(order[a]) - x.col(order[b])).template cast<double>().norm();
      worst = std::max(worst, (2 * r - d) / (2 * r));
    }
  return worst;
}

TYPED_TEST(Contact, FallingPileNeverOverlapsMoreThanOnePercent) {
  using Real = TypeParam;
  const double r = 0.02;
  for (Solver s : kSolvers) {
    World<Real> w = pile<Real>(s, r, 10);
    ASSERT_GE(w.num_particles(), 1000u);
    double worst = 0, lowest = 1e9;
    for (int step = 0; step < 60; ++step) {  // 1 s: every layer lands and the pile settles
      w.step();
      worst = std::max(worst, worst_overlap(w, r));
    }
    for (Index i = 0; i < w.num_particles(); ++i) lowest = std::min(lowest, double(w.positions()(2, i)));
    std::printf("CONTACT check=pile solver=%s real=%s worst_overlap=%.4g lowest_z=%.4g\n", std::string(name(s)).c_str(),
                real_name<Real>(), worst, lowest);
    EXPECT_LE(worst, 0.01) << name(s);
    EXPECT_GE(lowest, r * (1 - 0.01)) << name(s);  // and none sinks into the floor
  }
}

// A cloth of nx × ny particles (rest edge `edge`) folded over on the ground: along x it lies flat, turns through a
// half circle of radius 1.5 edges and comes back flat above itself, the upper layer falling at 2 m/s. Stretch on
// rows, columns and one diagonal per quad (rest lengths the flat cloth's); particles of radius half the rest edge,
// self-colliding. Returns its triangles; `upper` gets the particles of the upper layer's flat part.
template <class Real>
std::vector<std::array<Index, 3>> folded_cloth(World<Real>& w, int nx, int ny, double edge, Solver s,
                                               std::vector<Index>& upper, bool self_collision = true) {
  const double r = 0.5 * edge, rho = 1.5 * edge, arc = kPi * rho;
  const double length = (nx - 1) * edge, s1 = 0.5 * (length - arc);
  for (int k = 0; k < ny; ++k)
    for (int i = 0; i < nx; ++i) {
      const double sx = i * edge;
      Vec3<Real> x, v = Vec3<Real>::Zero();
      if (sx <= s1) {
        x = Vec3<Real>(Real(sx), Real(k * edge), Real(r));
      } else if (sx <= s1 + arc) {
        const double phi = (sx - s1) / rho;
        x = Vec3<Real>(Real(s1 + rho * std::sin(phi)), Real(k * edge), Real(r + rho * (1 - std::cos(phi))));
      } else {
        x = Vec3<Real>(Real(s1 - (sx - s1 - arc)), Real(k * edge), Real(r + 2 * rho));
        v.z() = Real(-2);
        upper.push_back(Index(w.num_particles()));
      }
      w.add_particle(x, Real(0.01), v);
    }
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  std::vector<std::array<Index, 3>> triangles;
  auto id = [&](int i, int k) { return Index(k * nx + i); };
  for (int k = 0; k < ny; ++k)
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) w.add_stretch(id(i, k), id(i + 1, k), set, Real(edge));
      if (k + 1 < ny) w.add_stretch(id(i, k), id(i, k + 1), set, Real(edge));
      if (i + 1 < nx && k + 1 < ny) {
        w.add_stretch(id(i, k), id(i + 1, k + 1), set, Real(edge * std::sqrt(2.0)));
        triangles.push_back({id(i, k), id(i + 1, k), id(i + 1, k + 1)});
        triangles.push_back({id(i, k), id(i + 1, k + 1), id(i, k + 1)});
      }
    }
  const ContactMaterial<Real> cloth{Real(0.3), Real(0.2), Real(0)};
  w.add_contact_body({0, w.num_particles(), Real(r), cloth, self_collision});
  w.add_plane(Vec3<Real>(0, 0, 1), Real(0), ContactMaterial<Real>{Real(0.5), Real(0.4), Real(0)});
  StepParams<Real> p = params<Real>(s, 4, 10);
  p.collision_margin = Real(0.2 * edge);
  w.set_params(p);
  return triangles;
}

// Whether point q crosses triangle (a, b, c) while all four move linearly from their `0` to their `1` positions:
// the roots in [0, 1] of the cubic f(t) = (q − a)·((b − a) × (c − a)) (the point in the triangle's plane), each
// checked for the point inside the triangle then.
bool crosses(const Eigen::Vector3d (&from)[4], const Eigen::Vector3d (&to)[4]) {
  using V = Eigen::Vector3d;
  const V u0 = from[0] - from[1], v0 = from[2] - from[1], w0 = from[3] - from[1];
  const V u1 = (to[0] - to[1]) - u0, v1 = (to[2] - to[1]) - v0, w1 = (to[3] - to[1]) - w0;
  const double c0 = u0.dot(v0.cross(w0));
  const double c1 = u1.dot(v0.cross(w0)) + u0.dot(v0.cross(w1) + v1.cross(w0));
  const double c2 = u1.dot(v0.cross(w1) + v1.cross(w0)) + u0.dot(v1.cross(w1));
  const double c3 = u1.dot(v1.cross(w1));
  auto f = [&](double t) { return ((c3 * t + c2) * t + c1) * t + c0; };
  std::vector<double> cuts = {0.0, 1.0};  // f is monotone between the roots of f'
  const double a = 3 * c3, b = 2 * c2, c = c1;
  if (std::abs(a) > 1e-300) {
    const double disc = b * b - 4 * a * c;
    if (disc >= 0)
      for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)})
        if (t > 0 && t < 1) cuts.push_back(t);
  } else if (std::abs(b) > 1e-300 && -c / b > 0 && -c / b < 1) {
    cuts.push_back(-c / b);
  }
  std::sort(cuts.begin(), cuts.end());
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    double lo = cuts[k], hi = cuts[k + 1];
    if ((f(lo) > 0) == (f(hi) > 0) && f(lo) != 0 && f(hi) != 0) continue;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      ((f(lo) > 0) == (f(mid) > 0) ? lo : hi) = mid;
    }
    const double t = 0.5 * (lo + hi);
    V at[4];
    for (int j = 0; j < 4; ++j) at[j] = from[j] + t * (to[j] - from[j]);
    const V n = (at[2] - at[1]).cross(at[3] - at[1]);
    const double area2 = n.squaredNorm();
    if (!(area2 > 0)) continue;
    // barycentric coordinates of the point in the triangle's plane
    const double l1 = (at[3] - at[2]).cross(at[0] - at[2]).dot(n) / area2;
    const double l2 = (at[1] - at[3]).cross(at[0] - at[3]).dot(n) / area2;
    const double l3 = 1 - l1 - l2;
    if (l1 >= 0 && l2 >= 0 && l3 >= 0) return true;
  }
  return false;
}

// Steps the world `steps` times and counts (point, triangle) crossings over every step, continuously.
template <class Real> int count_crossings(World<Real>& w, const std::vector<std::array<Index, 3>>& triangles, int steps) {
  Matrix3X<double> before = w.positions().template cast<double>();
  int crossings = 0;
  for (int step = 0; step < steps; ++step) {
    w.step();
    const Matrix3X<double> after = w.positions().template cast<double>();
    const Matrix3X<double> low = before.cwiseMin(after), high = before.cwiseMax(after);  // each path's box
    for (const auto& tri : triangles) {  // every point against every triangle whose swept boxes meet
      Eigen::Vector3d lo = low.col(tri[0]), hi = high.col(tri[0]);
      for (int j = 1; j < 3; ++j) {
        lo = lo.cwiseMin(low.col(tri[j]));
        hi = hi.cwiseMax(high.col(tri[j]));
      }
      for (Index q = 0; q < w.num_particles(); ++q) {
        if (low(0, q) > hi.x() || high(0, q) < lo.x() || low(1, q) > hi.y() || high(1, q) < lo.y() ||
            low(2, q) > hi.z() || high(2, q) < lo.z() || q == tri[0] || q == tri[1] || q == tri[2])
          continue;
        const Eigen::Vector3d from[4] = {before.col(q), before.col(tri[0]), before.col(tri[1]), before.col(tri[2])};
        const Eigen::Vector3d to[4] = {after.col(q), after.col(tri[0]), after.col(tri[1]), after.col(tri[2])};
        crossings += crosses(from, to) ? 1 : 0;
      }
    }
    before = after;
  }
  return crossings;
}

TYPED_TEST(Contact, FoldedClothNeverCrossesItself) {
  using Real = TypeParam;
  const double edge = 0.05;
  for (Solver s : kSolvers) {
    World<Real> w;
    std::vector<Index> upper;
    const auto triangles = folded_cloth<Real>(w, 24, 12, edge, s, upper);
    const int crossings = count_crossings(w, triangles, 300);
    // At rest the upper layer lies on the lower one: its centres one particle diameter (the cloth's thickness)
    // above the lower layer's, which lie one radius above the ground.
    double lowest = 1e9;
    for (Index q : upper) lowest = std::min(lowest, double(w.positions()(2, q)));
    std::printf("CONTACT check=cloth_fold solver=%s real=%s crossings=%d upper_layer_z=%.5g thickness_z=%.5g\n",
                std::string(name(s)).c_str(), real_name<Real>(), crossings, lowest, 1.5 * edge);
    EXPECT_EQ(crossings, 0) << name(s);
    EXPECT_GE(lowest, 1.5 * edge * 0.99) << name(s);
    EXPECT_LE(lowest, 1.5 * edge * 1.2) << name(s);  // it fell onto the lower layer (from 3.5 edges)
  }
}

TYPED_TEST(Contact, FoldedClothWithoutSelfCollisionFallsThroughItself) {  // the crossing check can fail
  using Real = TypeParam;
  World<Real> w;
  std::vector<Index> upper;
  const auto triangles = folded_cloth<Real>(w, 24, 12, 0.05, Solver::colored, upper, false);
  EXPECT_GT(count_crossings(w, triangles, 100), 0);
}

// Final positions and velocities of `world` stepped `steps` times with `solver` in an arena of `threads` threads.
template <class Real> std::vector<Real> run_on(const World<Real>& world, Solver solver, int threads, int steps) {
  World<Real> w = world;
  StepParams<Real> p = w.params();
  p.solver = solver;
  w.set_params(p);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    for (int i = 0; i < steps; ++i) w.step();
  });
  std::vector<Real> out(w.positions().data(), w.positions().data() + 3 * w.num_particles());
  out.insert(out.end(), w.velocities().data(), w.velocities().data() + 3 * w.num_particles());
  return out;
}

TYPED_TEST(Contact, ContactsGiveTheSameBitsOnOneToFourThreads) {
  using Real = TypeParam;
  std::vector<std::pair<const char*, World<Real>>> scenes;
  {
    World<Real> w = pile<Real>(Solver::colored, 0.02, 16);  // large enough to generate its contacts in parallel
    StepParams<Real> p = w.params();
    p.substeps = 2;
    w.set_params(p);
    scenes.emplace_back("pile of 4096", std::move(w));
  }
  {
    World<Real> w;
    std::vector<Index> upper;
    folded_cloth<Real>(w, 24, 12, 0.05, Solver::colored, upper);
    scenes.emplace_back("folded cloth", std::move(w));
  }
  for (const auto& [label, world] : scenes)
    for (Solver s : kSolvers) {
      const std::vector<Real> reference = run_on(world, s, 1, 12);
      for (int threads : {2, 3, 4})
        EXPECT_TRUE(reference == run_on(world, s, threads, 12)) << label << ", " << name(s) << ", " << threads << " threads";
    }
}

}  // namespace
}  // namespace pbd
