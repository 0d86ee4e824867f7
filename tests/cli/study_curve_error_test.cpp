// The study's error for fibers on a curve (cli/study_scenes.hpp: curve_errors): each fiber's tension from λ against
// its curve's force at its strain, in % of its set's force at yield.
#include "study_scenes.hpp"

#include <gtest/gtest.h>

namespace pbd::cli {
namespace {

// One fiber of 1 cm from a pinned particle to a free one of 1 t (so that one step leaves it stretched), started at
// 5% strain, no gravity: k = 1000 N, yield at 10% (F_y = 100 N).
World<double> one_fiber() {
  World<double> w;
  w.add_particle({0, 0, 0}, World<double>::kPinned);
  w.add_particle({0.0105, 0, 0}, 1e3);
  Material m;
  m.stiffness = 1000.0;
  m.yield_strain = 0.1;
  w.add_fiber(0, 1, w.add_constraint_set(Stiffness::fiber(m)), 0.01);
  StepParams<double> p;
  p.gravity.setZero();
  p.iterations = 4;
  w.set_params(p);
  return w;
}

TEST(StudyCurveError, ASolvedFiberIsOnItsCurveAndOneMovedOffItIsOffByKTimesTheStrain) {
  World<double> w = one_fiber();
  EXPECT_TRUE(has_curve(w));
  EXPECT_EQ(curve_errors(w).at("curve_pct").rms, 0.0);  // before a step a fiber has no force: nothing measured
  w.step();
  // One fiber is solved exactly in one projection: its tension is the curve's at its strain.
  EXPECT_LT(curve_errors(w).at("curve_pct").max, 1e-9);
  EXPECT_GT(w.fibers()[0].force, 40.0);
  // 0.1 mm further: 1% more strain, 10 N more on the curve, and the same λ: 10% of F_y off.
  w.positions()(0, 1) += 1e-4;
  const ErrorValue e = curve_errors(w).at("curve_pct");
  EXPECT_NEAR(e.rms, 10.0, 1e-6);
  EXPECT_NEAR(e.max, 10.0, 1e-6);
}

// One tet of 1 cm edges along x, y, z, pinned but for its corner along the fiber direction x, a
// free particle of 1 t started at 5% strain: E = 1 MPa, yield at 10%. Solved, its stress is the curve's; moved 1%
// further with the same λ, it is off by E·1% = 10% of σ_y.
TEST(StudyCurveError, ATetFibersStressIsJudgedAgainstItsCurveInPascals) {
  World<double> w;
  w.add_particle({0, 0, 0}, World<double>::kPinned);
  w.add_particle({0.0105, 0, 0}, 1e3);
  w.add_particle({0, 0.01, 0}, World<double>::kPinned);
  w.add_particle({0, 0, 0.01}, World<double>::kPinned);
  Material m;
  m.stiffness = 1e6;
  m.yield_strain = 0.1;
  TetFiberConstraint<double> c = blank_constraint<TetFiberConstraint<double>>();
  c.particles = {0, 1, 2, 3};
  c.set = w.add_constraint_set(Stiffness::fiber(m));
  c.volume = 0.01 * 0.01 * 0.01 / 6.0;
  c.direction = {1, 0, 0};
  c.weights = {100.0, 0.0, 0.0};  // the rest shape's Dm⁻¹·x̂: an edge of 1 cm along x
  w.add(c, kAllFields);
  StepParams<double> p;
  p.gravity.setZero();
  p.iterations = 4;
  w.set_params(p);
  EXPECT_TRUE(has_curve(w));
  w.step();
  EXPECT_LT(curve_errors(w).at("curve_pct").max, 1e-9);
  EXPECT_GT(w.material_readings<TetFiberConstraint<double>>()[0].force, 4e4);  // Pa
  w.positions()(0, 1) += 1e-4;
  EXPECT_NEAR(curve_errors(w).at("curve_pct").rms, 10.0, 1e-6);
}

// A fiber between two pinned particles held at 10% strain, past its rupture strain (5%): the solve moves nothing, so
// it breaks carrying no force, 100 N off its curve there (F_y = 100 N). The break is judged: 100%, not a run left
// with nothing to judge (0).
TEST(StudyCurveError, AFiberThatBreaksOffItsCurveCountsAtItsBreak) {
  World<double> w;
  w.add_particle({0, 0, 0}, World<double>::kPinned);
  w.add_particle({0.011, 0, 0}, World<double>::kPinned);
  Material m;
  m.stiffness = 1000.0;
  m.yield_strain = 0.1;
  m.rupture_strain = 0.05;
  w.add_fiber(0, 1, w.add_constraint_set(Stiffness::fiber(m)), 0.01);
  StepParams<double> p;
  p.gravity.setZero();
  w.set_params(p);
  w.step();
  ASSERT_EQ(w.last_breaks().size(), 1u);
  EXPECT_TRUE(w.fibers().empty());
  EXPECT_NEAR(curve_errors(w).at("curve_pct").rms, 100.0, 1e-9);
  w.step();  // nothing left and nothing broke
  EXPECT_EQ(curve_errors(w).at("curve_pct").rms, 0.0);
}

TEST(StudyCurveError, AWorldWithoutACurveHasNone) {
  World<double> w;
  w.add_particle({0, 0, 0}, World<double>::kPinned);
  w.add_particle({0.01, 0, 0}, 1e-3);
  w.add_fiber(0, 1, w.add_constraint_set(Stiffness::xpbd_compliance(1e-6)));
  EXPECT_FALSE(has_curve(w));
}

}  // namespace
}  // namespace pbd::cli
