// `pbd study merge` and finish() on 150,000 records of 1,000 scenes: every pass is n log n (sorted, or looked up
// by scene), so this takes seconds; a pass that compares every record with every other (the Pareto front, dominance,
// strong scaling) or searches the scenes per record takes minutes, and ctest's TIMEOUT of this test
// (tests/cli/CMakeLists.txt) fails it. The results are checked against their definitions on a small report.
#include "pbd/error.hpp"
#include "study_report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// A shard's report: `records` records, half of them in scene "...big", the others spread over `scenes` - 1 scenes.
// Times and errors are drawn from a small set, so that there are ties; some errors are infinite or NaN.
Report shard(int index, int shards, int records, int scenes, const char* mode) {
  Report r;
  json names = json::array();
  // Long names alike but for their end, as generated scenes' are: comparing two of them costs what it does.
  const std::string prefix(64, 's');
  for (int s = 0; s < scenes; ++s) names.push_back(prefix + (s == 0 ? std::string("big") : std::to_string(1000 + s)));
  r.study = {{"mode", mode}, {"seconds", 1.0}, {"context", {{"cpu", "CPU"}, {"cores", 2}, {"load_before", 0.0}}},
             {"options", {{"scenes", names}, {"shard", std::to_string(index) + "/" + std::to_string(shards)}}}};
  for (int s = 0; s < scenes; ++s) {
    SceneInfo info;
    info.name = info.base = names[std::size_t(s)].get<std::string>();
    info.primary_error = "stretch_pct";
    r.scenes.push_back(info);
  }
  const char* solvers[] = {"serial", "colored", "jacobi"};
  for (int i = 0; i < records; ++i) {
    const int k = i * shards + index;  // distinct across shards
    Record c;
    c.scene = names[i % 2 == 0 ? 0 : std::size_t(1 + k % (scenes - 1))].get<std::string>();
    c.solver = solvers[k % 3];
    c.threads = c.solver == std::string("serial") ? 1 : 1 + k % 2;
    c.substeps = 1 + k % 7;
    c.iterations = 1 + k % 5;
    c.ms = {1.0 + k % 13, 2.0};
    c.ms_per_step = 1.0 + double((std::int64_t(k) * 7919) % 97);
    c.primary_error = k % 101 == 0 ? INFINITY : k % 103 == 0 ? NAN : double((std::int64_t(k) * 104729) % 89);
    c.state_hash = std::uint64_t(k);
    r.records.push_back(c);
  }
  finish(r);
  return r;
}

// The Pareto flag, dominance and best split by their definitions, over every pair.
bool pareto_by_definition(const Record& r, const std::vector<Record>& all) {
  return std::none_of(all.begin(), all.end(), [&](const Record& o) {
    return o.scene == r.scene && o.ms_per_step <= r.ms_per_step && o.primary_error <= r.primary_error &&
           (o.ms_per_step < r.ms_per_step || o.primary_error < r.primary_error);
  });
}

TEST(StudyMergeScale, MergesAHundredAndFiftyThousandRecords) {
  const int records = 75000, scenes = 1000;
  const Report merged = merge_reports({shard(1, 2, records, scenes, "study"), shard(2, 2, records, scenes, "study")},
                                      {"a.json", "b.json"});
  ASSERT_EQ(merged.records.size(), std::size_t(2 * records));
  EXPECT_EQ(merged.scenes.size(), std::size_t(scenes));
  EXPECT_EQ(merged.scenes.front().name, std::string(64, 's') + "big");
  // In the order of the options' scenes, then by budget and substeps.
  EXPECT_TRUE(std::is_sorted(merged.records.begin(), merged.records.begin() + records, [](const Record& a, const Record& b) {
    return std::make_pair(a.budget(), a.substeps) < std::make_pair(b.budget(), b.substeps);
  }));
  EXPECT_EQ(merged.records[std::size_t(records)].scene, std::string(64, 's') + "1001");
  EXPECT_FALSE(merged.dominance.empty());
  EXPECT_FALSE(merged.time_to_target.empty());
  std::ostream discard(nullptr);  // formats every line, keeps none
  print_table(discard, merged);
  print_csv(discard, merged);
}

TEST(StudyMergeScale, FinishesAHundredThousandRecordsOfAScalingStudy) {
  const Report report = shard(1, 1, 100000, 1000, "scaling");
  EXPECT_FALSE(report.strong.empty());
}

// The derived results of the n log n passes are those of their definitions.
TEST(StudyMergeScale, DerivedResultsFollowTheirDefinitions) {
  const Report report = shard(1, 1, 3000, 3, "scaling");
  for (const Record& r : report.records) EXPECT_EQ(r.pareto, pareto_by_definition(r, report.records)) << r.split();
  for (const Dominance& d : report.dominance) {
    std::vector<std::string> undominated;
    int serial = 0;
    for (const Record& s : report.records) {
      if (s.scene != d.scene || s.solver != "serial") continue;
      ++serial;
      const bool dominated = std::any_of(report.records.begin(), report.records.end(), [&](const Record& c) {
        return c.scene == s.scene && c.solver == d.solver && c.threads == d.threads && c.ms_per_step < s.ms_per_step &&
               c.primary_error <= s.primary_error;
      });
      if (!dominated) undominated.push_back(s.split());
    }
    EXPECT_EQ(d.serial_points, serial);
    EXPECT_EQ(d.undominated, undominated) << d.scene << " " << d.solver;
  }
  std::size_t strong = 0;
  for (const Record& r : report.records)
    strong += std::any_of(report.records.begin(), report.records.end(), [&](const Record& o) {
      return o.scene == r.scene && o.solver == r.solver && o.threads == 1 && o.substeps == r.substeps &&
             o.iterations == r.iterations;
    });
  EXPECT_EQ(report.strong.size(), strong);
}

}  // namespace
}  // namespace pbd::cli
