// An elastic scene is judged by its distance from the converged reference (`"primary_error": "reference"`,
// cli/study_record.hpp's kReferenceMeasure): finish() takes each record's primary error from ref_error_mm and its
// final one from trajectory_error_mm, and the Pareto front follows them, not the strain.
#include "study_report.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pbd::cli {
namespace {

Record record(const char* solver, double ms, double strain, std::optional<double> ref, double end) {
  Record r;
  r.scene = "bar";
  r.solver = solver;
  r.ms_per_step = ms;
  r.errors["neo_hookean"] = {strain, strain};
  r.primary_error = std::nan("");  // as the error run leaves it: the reference is measured later
  r.ref_error_mm = ref;
  r.trajectory_error_mm = end;
  return r;
}

TEST(StudyReferenceError, ElasticScenesAreJudgedByTheirDistanceFromTheReference) {
  Report report;
  report.study = {{"mode", "study"}, {"context", nlohmann::json::object()}};
  SceneInfo bar;
  bar.name = bar.base = "bar";
  bar.primary_error = kReferenceMeasure;
  report.scenes.push_back(bar);
  // The slow point has the larger strain but is the nearer to the reference: it is on the front, not dominated.
  report.records = {record("serial", 2.0, 5.0, 0.1, 0.3), record("colored", 1.0, 1.0, 0.5, 0.9),
                    record("jacobi", 3.0, 0.5, 0.7, 1.2)};
  finish(report);
  const auto& r = report.records;
  EXPECT_EQ(r[0].primary_error, 0.1);
  EXPECT_EQ(r[0].primary_error_final, 0.3);
  EXPECT_EQ(r[1].primary_error, 0.5);
  EXPECT_TRUE(r[0].pareto);
  EXPECT_TRUE(r[1].pareto);
  EXPECT_FALSE(r[2].pareto) << "slower and farther from the reference than both";
  // With no reference measured (scaling mode) the primary error is NaN, never 0.
  report.records = {record("colored", 1.0, 1.0, std::nullopt, 0.0)};
  report.records[0].trajectory_error_mm.reset();
  finish(report);
  EXPECT_TRUE(std::isnan(report.records[0].primary_error));
  EXPECT_TRUE(std::isnan(report.records[0].primary_error_final));
}

// The reference of such a scene is checked by positions alone: its strain is not an error to be a tenth of.
TEST(StudyReferenceError, ItsReferenceIsCheckedByPositionsNotByTheStrain) {
  std::vector<Record> records = {record("colored", 1.0, 1.0, 0.5, 0.9)};
  Reference ref;
  ref.scene = "bar";
  ref.step_change_mm = 0.01;        // a tenth of 0.5 mm is 0.05: converged
  ref.trajectory_change_mm = 0.5;   // a tenth of 0.9 mm is 0.09: not
  ref.error_change["neo_hookean"] = {0.5, 0.5};  // half the smallest strain (1.0)
  check_reference(ref, records, false);
  EXPECT_FALSE(ref.converged);
  EXPECT_TRUE(ref.step_converged);
  EXPECT_EQ(ref.failures.size(), 2u) << "the run's end and the strain";
  check_reference(ref, records, true);
  EXPECT_EQ(ref.failures.size(), 1u) << "the run's end only";
  ref.trajectory_change_mm = 0.05;
  check_reference(ref, records, true);
  EXPECT_TRUE(ref.converged);
  ref.step_change_mm = 0.1;
  check_reference(ref, records, true);
  EXPECT_FALSE(ref.step_converged);
}

}  // namespace
}  // namespace pbd::cli
