// Physics against closed forms, for every solver (issue 20): what a step converges to must be the material the
// user asked for, whichever solver computes it. Each check prints one greppable line
//   PHYSICS check=<name> solver=<...> real=<float|double> <measured>=<x> <closed form>=<y> error=<relative>
// (`engine_tests --gtest_filter='Physics*'` or `ctest -R Physics -V`); docs/robustness.md quotes them.
//   - hanging chain: a compliant chain damped to rest stretches link k by α·T_k, T_k the weight below it
//   - chain period: a 10-mass compliant chain, fixed at one end, swings in its first normal mode at
//                   ω₁ = 2 √(k/m) sin(π / (2(2N + 1))), k = 1/α
//   - sag under damping: the same chain with strong damping sags by the whole of g (damping acts on motion only)
//   - free body: constraints that cannot all hold, no pins, contacts or gravity: linear momentum kept to rounding,
//                angular momentum within a stated bound
#include "pbd/io/build_world.hpp"
#include "pbd/io/generators.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/scene.hpp"
#include "pbd/metrics.hpp"
#include "pbd/world.hpp"
#include "hanging_chain.hpp"
#include "world_runs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

namespace pbd {
namespace {

template <class Real> class Physics : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Physics, Precisions);

constexpr double kPi = 3.14159265358979323846;


template <class Real> const char* real_name() { return sizeof(Real) == 4 ? "float" : "double"; }

void print_line(const char* check, Solver s, const char* real, const std::string& rest) {
  std::printf("PHYSICS check=%s solver=%s real=%s %s\n", check, std::string(name(s)).c_str(), real, rest.c_str());
}

std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

using test::hanging_chain;

// The hanging chain's extension at rest, α Σ_k T_k with T_k = (n − k + 1) m g, against the run's.
template <class Real>
void check_hanging_chain(const char* check, int n, double damping, int substeps, int iterations, int jacobi_iterations,
                         double tolerance) {
  const double m = 0.01, rest = 0.05, alpha = 1e-3, g = 9.81;
  double closed = 0;
  for (int k = 1; k <= n; ++k) closed += alpha * (n - k + 1) * m * g;
  for (Solver s : kSolvers) {
    World<Real> w = hanging_chain<Real>(n, m, rest, alpha, s);
    StepParams<Real> p = w.params();
    p.damping = Real(damping);
    p.substeps = substeps;
    p.iterations = s == Solver::jacobi ? jacobi_iterations : iterations;
    w.set_params(p);
    for (int step = 0; step < 600; ++step) w.step();  // 10 s: damped to rest
    const double extension = -double(w.positions()(2, n)) - n * rest;
    const double error = extension / closed - 1;
    print_line(check, s, real_name<Real>(),
               "extension=" + fmt(extension) + " closed_form=" + fmt(closed) + " error=" + fmt(error) +
                   " speed=" + fmt(double(w.velocities().norm())));
    EXPECT_LT(std::abs(error), tolerance) << name(s);
  }
}

TYPED_TEST(Physics, CompliantHangingChainStretchesByAlphaTimesTension) {
  check_hanging_chain<TypeParam>("hanging-chain", 30, 1.0, 10, 10, 10, 0.01);
}

// Jacobi's over-relaxation ω scales the correction it applies and the λ it accumulates alike, so it converges to
// the same material for any ω in (0, 2) (it used to add the full Δλ to λ while applying ω/n of it). 40 sweeps a
// sub-step: at ω = 0.5 each sweep does half as much, and 10 leave it 6.5% short of converged.
TYPED_TEST(Physics, JacobiReachesTheSameExtensionForAnyOmega) {
  using Real = TypeParam;
  const int n = 30;
  const double m = 0.01, rest = 0.05, alpha = 1e-3, g = 9.81;
  double closed = 0;
  for (int k = 1; k <= n; ++k) closed += alpha * (n - k + 1) * m * g;
  for (double omega : {0.5, 1.0, 1.5}) {
    World<Real> w = hanging_chain<Real>(n, m, rest, alpha, Solver::jacobi);
    StepParams<Real> p = w.params();
    p.damping = Real(1);
    p.substeps = 10;
    p.iterations = 40;
    p.jacobi_omega = Real(omega);
    w.set_params(p);
    for (int step = 0; step < 600; ++step) w.step();
    const double error = (-double(w.positions()(2, n)) - n * rest) / closed - 1;
    print_line("jacobi-omega", Solver::jacobi, real_name<Real>(), "omega=" + fmt(omega) + " error=" + fmt(error));
    EXPECT_LT(std::abs(error), 0.01) << omega;
  }
}

// Damping 2/s at h = 1/60 (one sub-step) on a chain short enough for the sweeps to converge within each step:
// damping applied after gravity would leave 1 − d·h = 0.967 of the sag. Each sub-step starts λ from 0, and a Jacobi
// sweep on this stiff chain (α̃ = α/h² = 3.6 against split masses Σ n w = 400) removes only ~6% of the error, so
// Jacobi gets 300 sweeps where Gauss-Seidel needs 40.
TYPED_TEST(Physics, DampingDoesNotLowerTheSagAtRest) {
  check_hanging_chain<TypeParam>("sag-under-damping", 3, 2.0, 1, 40, 300, 0.001);
}

// Fixed-free chain of n masses m and springs k = 1/α along x, no gravity, started at rest in its first mode
// u_j = A sin(jθ), θ = π/(2n + 1): the free end's displacement is A sin(nθ) cos(ω₁ t). The period is measured from
// the times it crosses zero (linearly interpolated), over the first 4 periods.
TYPED_TEST(Physics, CompliantChainSwingsWithItsNormalModePeriod) {
  using Real = TypeParam;
  const int n = 10;
  const double m = 0.01, rest = 0.1, alpha = 0.01, amplitude = 0.002;
  const double theta = kPi / (2 * n + 1);
  const double omega = 2 * std::sqrt(1 / (alpha * m)) * std::sin(theta / 2);
  const double period = 2 * kPi / omega;
  for (Solver s : kSolvers) {
    for (int iterations : {20, 100}) {
      World<Real> w;
      const Index set = w.add_constraint_set(Stiffness::xpbd_compliance(alpha));
      w.add_particle(Vec3<Real>::Zero(), World<Real>::kPinned);
      for (int j = 1; j <= n; ++j) {
        w.add_particle(Vec3<Real>(Real(rest * j + amplitude * std::sin(j * theta)), 0, 0), Real(m));
        w.add_stretch(j - 1, j, set, Real(rest));
      }
      StepParams<Real> p;
      p.gravity.setZero();
      p.substeps = 10;
      p.iterations = iterations;
      p.solver = s;
      w.set_params(p);
      std::vector<double> crossings;
      double prev = amplitude * std::sin(n * theta), t_prev = 0;
      while (crossings.size() < 9 && w.time() < 10 * period) {
        w.step();
        const double u = double(w.positions()(0, n)) - rest * n;
        if ((u < 0) != (prev < 0)) crossings.push_back(t_prev + (w.time() - t_prev) * prev / (prev - u));
        prev = u;
        t_prev = w.time();
      }
      ASSERT_EQ(crossings.size(), 9u) << name(s) << " stopped swinging";
      const double measured = (crossings[8] - crossings[0]) / 4;
      const double error = measured / period - 1;
      print_line("chain-period", s, real_name<Real>(),
                 "iterations=" + std::to_string(iterations) + " period=" + fmt(measured) + " closed_form=" +
                     fmt(period) + " error=" + fmt(error));
      EXPECT_LT(std::abs(error), 0.01) << name(s) << " " << iterations;
    }
  }
}

// The angular velocity ω = I⁻¹ L of a world's movable particles about their centre of mass (rad/s): how fast the
// body turns as a whole.
template <class Real> Vec3<double> rigid_spin(const World<Real>& w) {
  const auto x = w.positions();
  const auto v = w.velocities();
  const auto inv = w.inverse_masses();
  double mass = 0;
  Vec3<double> c = Vec3<double>::Zero();
  for (Index i = 0; i < w.num_particles(); ++i)
    if (inv[i] > Real(0)) {
      mass += 1 / double(inv[i]);
      c += x.col(i).template cast<double>() / double(inv[i]);
    }
  c /= mass;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Vec3<double> l = Vec3<double>::Zero();
  for (Index i = 0; i < w.num_particles(); ++i) {
    if (!(inv[i] > Real(0))) continue;
    const double m = 1 / double(inv[i]);
    const Vec3<double> r = x.col(i).template cast<double>() - c;
    l += m * r.cross(Vec3<double>(v.col(i).template cast<double>()));
    inertia += m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return inertia.ldlt().solve(l);
}

// A free dodecahedron (no pins, contacts or gravity) whose hard volume is held at 2x by stretch constraints that
// want the rest size (compliance 1e-4): they cannot all hold, and the sweeps never settle (a limit cycle). Every
// projection moves the particles by w_i ∇C Δλ with Σ_i ∇_i C = 0 (stretch, bending and volume are translation
// invariant), so the linear momentum stays 0 up to rounding. Angular momentum: each projection is central about the
// positions it reads, not about the start of the sub-step, and Gauss-Seidel's fixed order turned that into a spin of
// 50 rad/s; the velocity update now gives a free body back the angular momentum it had before the solve
// (free_bodies.hpp), so it too stays 0 up to rounding. Bounds: 2·10⁴ rounding errors of the body's momentum scale
// (1 kg at 1 m/s, over 0.3 m for L): 2400 sub-steps each round Σ m v over 20 particles a few times.
template <class Real> void check_free_body(Solver s, SweepOrder order) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::xpbd_compliance(1e-4));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.1));
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.pressure = {2.0, 2.0, 0.0};
  MeshBodyOptions o;
  o.mass = 1.0;
  add_mesh(w, dodecahedron_mesh(0.3), o, sets);
  StepParams<Real> p;
  p.gravity.setZero();
  p.substeps = 4;
  p.iterations = 5;
  p.damping = Real(0.5);
  p.solver = s;
  p.sweep_order = order;
  w.set_params(p);
  double max_p = 0, max_l = 0, max_spin = 0;
  for (int step = 0; step < 600; ++step) {
    w.step();
    const auto [mom, ang] = test::momenta(w);
    max_p = std::max(max_p, mom.norm());
    max_l = std::max(max_l, ang.norm());
    max_spin = std::max(max_spin, rigid_spin(w).norm());
  }
  print_line("free-body", s, real_name<Real>(),
             std::string("order=") + std::string(name(order)) + " max_momentum=" + fmt(max_p) +
                 " max_angular_momentum=" + fmt(max_l) + " max_spin=" + fmt(max_spin));
  const double eps = std::numeric_limits<Real>::epsilon();
  EXPECT_LE(max_p, 2e4 * eps * 1.0) << name(s) << " " << name(order);
  EXPECT_LE(max_l, 2e4 * eps * 1.0 * 0.3) << name(s) << " " << name(order);
}

TYPED_TEST(Physics, FreeBodyKeepsItsMomentum) {
  for (Solver s : kSolvers)
    for (SweepOrder order : {SweepOrder::forward, SweepOrder::symmetric})
      if (s != Solver::jacobi || order == SweepOrder::forward) check_free_body<TypeParam>(s, order);
}

// The built-in inflation scenes, run for 10 s with their own (symmetric) sweep order: the volume reaches its target
// (0.1%) and holds it, and the body does not turn. Also the dodecahedron with the over-constrained stretch the seed
// gave it (compliance 1e-3: its stretch fights the volume far harder). The forward order is run too for the
// dodecahedrons and printed, not checked: it rolls the over-constrained one on the ground at 25-27 rad/s (its
// contacts along +z leave only the spin about z to free_bodies.hpp; the symmetric order is what stops the roll).
Scene inflation_scene(const std::string& which) {
  if (which != "inflate-overconstrained") return load_scene_by_name(which, PBD_TEST_SCENE_DIR);
  std::ifstream in(std::string(PBD_TEST_SCENE_DIR) + "/inflate.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string soft = "\"stretch\": {\"compliance\": 0.01}";
  const std::size_t at = text.find(soft);
  EXPECT_NE(at, std::string::npos) << "inflate.json changed";
  if (at != std::string::npos) text.replace(at, soft.size(), "\"stretch\": {\"compliance\": 0.001}");
  return parse_scene(text, "inflate.json with stretch compliance 1e-3");
}

// One scene for 10 s under serial, colored and Jacobi with its own (symmetric) sweeps; with `forward_too`, with
// forward sweeps as well, printed for comparison and not checked.
void check_inflation(const std::string& scene, bool forward_too) {
  for (Solver s : kSolvers) {
    if (s == Solver::serial_colored) continue;  // colored's bits
    for (SweepOrder order : {SweepOrder::symmetric, SweepOrder::forward}) {
      if (order == SweepOrder::forward && !forward_too) continue;
      World<double> w = build_world<double>(inflation_scene(scene).world);
      StepParams<double> p = w.params();
      EXPECT_EQ(p.sweep_order, SweepOrder::symmetric) << scene;
      p.solver = s;
      p.sweep_order = order;
      w.set_params(p);
      for (int step = 0; step < 600; ++step) w.step();
      const auto& v = w.volumes();
      const double target = v.items[0].rest * v.items[0].pressure.at(w.time());
      const double volume = double(six_volume<double>(v.triangles, Matrix3X<double>(w.positions())));
      const double error = volume / target - 1;
      const double spin = rigid_spin(w).norm();
      print_line("inflation", s, "double",
                 "scene=" + scene + " order=" + std::string(name(order)) + " volume_error=" + fmt(error) +
                     " spin=" + fmt(spin));
      if (order == SweepOrder::forward) continue;  // for comparison
      EXPECT_LT(std::abs(error), 1e-3) << scene << " " << name(s);
      EXPECT_LT(spin, 0.5) << scene << " " << name(s);
    }
  }
}

TEST(Physics, InflateReachesItsTargetWithoutSpinning) { check_inflation("inflate", true); }
TEST(Physics, InflateMeshReachesItsTargetWithoutSpinning) { check_inflation("inflate-mesh", false); }
TEST(Physics, OverConstrainedInflateDoesNotSpinUnderSymmetricSweeps) {
  check_inflation("inflate-overconstrained", true);
}

// Contacts take energy away, never add it: the built-in cloth dropped onto the ground alone and onto the sphere and
// the ground, for every solver and precision. From the first step with a contact on, the total energy (kinetic +
// gravitational) never exceeds what it was at that step, and, for Gauss-Seidel, never rises by more than 1% of it
// between any two later steps (the cloth's bending is soft and its stretch hard, so they store next to nothing; what
// rises is the few sweeps' leftover stretch error springing back). Jacobi's 4 sweeps leave the falling cloth
// stretched (its mean height at landing is 0.14 m against 0.25 m), and recovering from that raises it again (0.8 J)
// without leaving the floor, so it gets only the first bound. And the cloth does not leave the floor once it has
// landed: from the first step a particle is within the collision margin of the ground, some particle stays there.
// (Before issue 20 the demo's bending was stiff, PBD k = 0.05 over 40 projections a step: the folds it made on
// landing sprang back, raised the energy by 1.2 J and threw the whole cloth 0.15-0.2 m off the floor.)
template <class Real> void check_cloth_landing(bool sphere) {
  for (Solver s : kSolvers) {
    if (s == Solver::serial_colored) continue;  // colored's bits
    Scene scene = load_scene_by_name("cloth", PBD_TEST_SCENE_DIR);
    if (!sphere) scene.world.spheres.clear();
    World<Real> w = build_world<Real>(scene.world);
    StepParams<Real> p = w.params();
    p.solver = s;
    w.set_params(p);
    const double margin = double(p.collision_margin);
    double e_contact = std::numeric_limits<double>::quiet_NaN(), worst_gain = -1e300, highest_low_point = 0;
    double lowest_e = 1e300, worst_rise = 0;
    bool landed = false;
    for (int step = 0; step < 150; ++step) {  // 2.5 s: it lands at about 0.4 s, and used to jump at 0.5-1 s
      w.step();
      const double e = energy(w).total();
      if (std::isnan(e_contact) && !w.last_collisions().empty()) e_contact = e;
      if (!std::isnan(e_contact)) {
        worst_gain = std::max(worst_gain, e - e_contact);
        lowest_e = std::min(lowest_e, e);
        worst_rise = std::max(worst_rise, e - lowest_e);
      }
      const double low = double(w.positions().row(2).minCoeff());
      if (low <= margin) landed = true;
      if (landed) highest_low_point = std::max(highest_low_point, low);
    }
    print_line(sphere ? "cloth-on-sphere-and-ground" : "cloth-on-ground", s, real_name<Real>(),
               "energy_at_first_contact=" + fmt(e_contact) + " max_gain_after=" + fmt(worst_gain) +
                   " max_rise_after=" + fmt(worst_rise) +
                   " highest_low_point_after_landing=" + fmt(highest_low_point));
    ASSERT_FALSE(std::isnan(e_contact)) << name(s) << ": never touched anything";
    EXPECT_LE(worst_gain, 1e-6 * std::abs(e_contact) + 1e-9) << name(s);
    if (s != Solver::jacobi) {
      EXPECT_LE(worst_rise, 0.01 * std::abs(e_contact)) << name(s);
    }
    EXPECT_LE(highest_low_point, margin) << name(s);
  }
}

TYPED_TEST(Physics, ClothDroppedOntoTheGroundGainsNoEnergyAndStaysDown) { check_cloth_landing<TypeParam>(false); }
TYPED_TEST(Physics, ClothDroppedOntoTheSphereGainsNoEnergyAndStaysDown) { check_cloth_landing<TypeParam>(true); }

}  // namespace
}  // namespace pbd
