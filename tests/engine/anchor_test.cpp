// Anchor constraint: analytic projection, stiffness, gradient, pinned particles, the at-target guard.
#include "constraint_checks.hpp"
#include "pbd/constraints/anchor.hpp"

namespace pbd {
namespace {

TEST(Anchor, UnitStiffnessMovesTheParticleToTheTarget) {
  double p[3] = {1, 2, 3};
  const double w[1] = {0.5};
  double lambda = 0;
  project(AnchorConstraint<double>{{0}, 0, {0, 0, 1}}, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_NEAR(p[0], 0, 1e-12);
  EXPECT_NEAR(p[1], 0, 1e-12);
  EXPECT_NEAR(p[2], 1, 1e-12);
}

TEST(Anchor, HalfStiffnessMovesHalfway) {
  float p[3] = {0, 0, 4};
  const float w[1] = {2};
  float lambda = 0;
  project(AnchorConstraint<float>{{0}, 0, {0, 0, 0}}, p, w, SolveCoefficients<float>{0.5f, 0}, lambda);
  EXPECT_NEAR(p[2], 2.0f, 1e-6f);
}

TEST(Anchor, PinnedParticleNeverMoves) {
  double p[3] = {1, 1, 1};
  const double w[1] = {0};
  double lambda = 0;
  project(AnchorConstraint<double>{{0}, 0, {0, 0, 0}}, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_EQ(p[0], 1);
  EXPECT_EQ(p[1], 1);
  EXPECT_EQ(p[2], 1);
}

TEST(Anchor, AtTheTargetNothingMovesAndNothingIsNaN) {
  double p[3] = {0.5, 0.5, 0.5};
  const double w[1] = {1};
  double lambda = 0;
  project(AnchorConstraint<double>{{0}, 0, {0.5, 0.5, 0.5}}, p, w, SolveCoefficients<double>{1, 0}, lambda);
  EXPECT_EQ(p[0], 0.5);
  EXPECT_EQ(lambda, 0.0);
}

TEST(Anchor, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(4);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3<double> p[1] = {test::random_point<double>(rng)};
    checked += test::check_gradient(AnchorConstraint<double>{{0}, 0, test::random_point<double>(rng)}, p);
  }
  EXPECT_EQ(checked, 200);
}

}  // namespace
}  // namespace pbd
