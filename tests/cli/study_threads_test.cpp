// `pbd study --threads` above what the machine runs is refused (its points would be reported as timed on threads
// that never ran), but with --estimate, which runs nothing; the default thread counts never exceed it
// (cli/study_options.hpp's make_plan and machine_threads).
#include "pbd/error.hpp"
#include "study_options.hpp"

#include <gtest/gtest.h>

#include <string>

namespace pbd::cli {
namespace {

StudyOptions options(const std::string& threads) {
  StudyOptions o;
  o.scenes = {"cloth30"};  // a generated scene: no scene folder needed
  o.threads = threads;
  return o;
}

TEST(StudyThreads, MoreThanTheMachineRunsAreRefused) {
  const int most = machine_threads();
  ASSERT_GE(most, 1);
  const std::string over = std::to_string(most + 1);
  try {
    (void)make_plan(options("1," + over));
    FAIL() << "--threads 1," << over << " was accepted on a machine of " << most << " threads";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "--threads: " + over + " is more than the " + std::to_string(most) +
                                         " threads this machine runs (its points would be timed on " +
                                         std::to_string(most) + "); give at most " + std::to_string(most));
  }
  EXPECT_THROW((void)make_plan(options("1000")), Error);
  EXPECT_EQ(make_plan(options(std::to_string(most))).threads.back(), most);
}

TEST(StudyThreads, AnEstimateMayPlanForAnotherMachine) {
  StudyOptions o = options("1," + std::to_string(machine_threads() + 1));
  o.estimate = true;
  EXPECT_EQ(make_plan(o).threads.back(), machine_threads() + 1);
}

TEST(StudyThreads, TheDefaultsStayWithinTheMachine) {
  EXPECT_LE(make_plan(options("")).threads.back(), machine_threads());
  StudyOptions scaling = options("");
  scaling.scaling = true;
  EXPECT_EQ(make_plan(scaling).threads.back(), machine_threads());
}

}  // namespace
}  // namespace pbd::cli
