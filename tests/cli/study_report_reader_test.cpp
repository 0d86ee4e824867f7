// A study report read back (cli/study/report_reader.hpp) is checked field by field: what pbd wrote reads back; a
// missing key, a value of another type or out of its range, an empty list of rounds, nesting deeper than the limit,
// a key given twice, a NUL byte and a file that is not a regular file are refused with a pbd::Error naming the file
// and the key. The writer handles an empty list of rounds too.
#include "json_file.hpp"
#include "pbd/error.hpp"
#include "report_reader.hpp"
#include "study_report.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// A small report as `pbd study` makes it: one scene, its reference, two records, one shared-nothing run.
Report sample_report() {
  Report r;
  r.study = {{"pbd_version", "0.1.0"},
             {"git_commit", "abc"},
             {"mode", "study"},
             {"seconds", 1.5},
             {"context",
              {{"cpu", "CPU"}, {"cores", 2}, {"host", "h"}, {"compiler", "gcc"}, {"flags", "-O3"},
               {"build_type", "Release"}, {"load_before", 0.0}, {"load_during", 0.1}, {"load_during_max", 1.0}}},
             {"options",
              {{"scenes", json::array({"rope"})}, {"solvers", json::array({"serial", "colored"})},
               {"threads", json::array({1, 2})}, {"precision", "float"}, {"repeats", 2}, {"steps", "scene"},
               {"quick", true}, {"variants", json::array({"plain"})}, {"target_pct", 1.0},
               {"default_solvers", false}, {"shard", nullptr}, {"budgets", json::array({2})},
               {"reference",
                {{"solver", "colored"}, {"substeps", 8}, {"iterations", 1}, {"max_budget", 8},
                 {"max_seconds", 2.0}}}}}};
  SceneInfo s;
  s.name = s.base = "rope";
  s.particles = 10;
  s.constraints = 9;
  s.steps = 20;
  s.size_m = 1.0;
  s.primary_error = "stretch_pct";
  s.measures = {"stretch_pct"};
  r.scenes.push_back(s);
  Reference ref;
  ref.scene = "rope";
  ref.solver = "colored";
  ref.substeps = 8;
  ref.iterations = 1;
  ref.steps = 20;
  ref.threads = 2;
  ref.seconds = 0.2;
  ref.errors = ref.errors_final = {{"stretch_pct", {0.01, 0.02}}};
  ref.step_change_mm = 0.001;
  ref.trajectory_change_mm = 0.002;
  ref.error_change = {{"stretch_pct", {0.0001, 0.0002}}};
  ref.tried = {"4x1"};
  r.references.push_back(ref);
  for (const char* solver : {"serial", "colored"}) {
    Record c;
    c.scene = "rope";
    c.solver = solver;
    c.threads = 1;
    c.substeps = 2;
    c.iterations = 1;
    c.steps = 20;
    c.precision = "float";
    c.repeats = 2;
    c.ms = {0.1, 0.12};
    c.ms_per_step = 0.11;
    c.ms_per_step_min = 0.1;
    c.ms_per_step_max = 0.12;
    c.ms_per_step_cv = 0.05;
    c.particles = 10;
    c.constraints = 9;
    c.colors = 2;
    c.timing_steps = 20;
    c.errors = c.errors_final = {{"stretch_pct", {0.5, 1.0}}};
    c.primary_error = c.primary_error_final = 0.5;
    c.ref_error_mm = 0.1;
    c.ref_error_max_mm = 0.2;
    c.trajectory_error_mm = 0.3;
    c.energy_drift = -0.01;
    c.state_hash = 0x0123456789abcdefULL;
    r.records.push_back(c);
  }
  r.shared_nothing.push_back({"rope", 2, {1.5, 1.7, 1.6}});
  finish(r);
  return r;
}

// The pbd::Error `read` throws, or "(no error)".
template <class F> std::string error_of(F&& read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string refusal(const json& doc) { return error_of([&] { (void)report_from_json(doc, "a.json"); }); }

TEST(StudyReportReader, ReadsBackWhatItWrites) {
  const Report original = sample_report();
  const Report back = parse_report(report_json(original).dump(1), "a.json");
  ASSERT_EQ(back.records.size(), 2u);
  EXPECT_EQ(back.records[1].solver, "colored");
  EXPECT_EQ(back.records[1].state_hash, 0x0123456789abcdefULL);
  EXPECT_EQ(back.records[1].ms, original.records[1].ms);
  EXPECT_EQ(back.records[1].energy_drift, -0.01);
  EXPECT_EQ(back.references.at(0).tried, std::vector<std::string>{"4x1"});
  EXPECT_EQ(back.shared_nothing.at(0).speedups, (std::vector<double>{1.5, 1.7, 1.6}));
  EXPECT_EQ(report_json(back), report_json(original));
}

TEST(StudyReportWriter, WritesASharedNothingRunWithNoRounds) {
  Report report = sample_report();
  report.shared_nothing.front().speedups.clear();
  const json doc = report_json(report);
  EXPECT_TRUE(doc["shared_nothing"][0]["speedup"].is_null());
  EXPECT_TRUE(doc["shared_nothing"][0]["speedup_min"].is_null());
  std::ostringstream table;
  print_table(table, report);
  EXPECT_NE(table.str().find("shared-nothing split on 2 threads (this machine's ceiling): no rounds"),
            std::string::npos);
}

TEST(StudyReportReader, RefusesASharedNothingRunWithNoRounds) {
  json doc = report_json(sample_report());
  doc["shared_nothing"][0]["speedups"] = json::array();
  EXPECT_EQ(refusal(doc), "a.json: shared_nothing[0].speedups: the list is empty");
}

TEST(StudyReportReader, NamesTheFileAndKeyOfAMissingKey) {
  const json doc = report_json(sample_report());
  for (const auto& [pointer, key] : std::vector<std::pair<std::string, std::string>>{
           {"/study/options", "study.options"}, {"/study/context", "study.context"},
           {"/study/options/threads", "study.options.threads"}, {"/records/1/state_hash", "records[1].state_hash"},
           {"/records/0/ms_runs", "records[0].ms_runs"}, {"/scenes/0/steps", "scenes[0].steps"},
           {"/references/0/errors", "references[0].errors"}, {"/shared_nothing", "shared_nothing"},
           {"/records/0/errors/stretch_pct/max", "records[0].errors.stretch_pct.max"},
           {"/shared_nothing/0/threads", "shared_nothing[0].threads"}}) {
    json edited = doc;
    const json::json_pointer p(pointer);
    edited[p.parent_pointer()].erase(p.back());
    EXPECT_EQ(refusal(edited), "a.json: " + key + ": missing") << pointer;
  }
}

// Every number of the report, set to a value of another type or out of its range, is refused naming its key.
TEST(StudyReportReader, RefusesCorruptedNumbersNamingTheKey) {
  const json doc = report_json(sample_report());
  struct Field {
    const char* pointer;
    const char* key;
    bool count;  // a positive integer: 0 and 2.5 are refused too
  };
  const Field fields[] = {
      {"/records/0/threads", "records[0].threads", true},
      {"/records/0/substeps", "records[0].substeps", true},
      {"/records/1/iterations", "records[1].iterations", true},
      {"/records/0/steps", "records[0].steps", true},
      {"/records/0/repeats", "records[0].repeats", true},
      {"/records/0/particles", "records[0].particles", true},
      {"/records/0/timing_steps", "records[0].timing_steps", true},
      {"/records/0/constraints", "records[0].constraints", false},
      {"/records/0/colors", "records[0].colors", false},
      {"/records/0/ms_per_step", "records[0].ms_per_step", false},
      {"/records/0/ms_per_step_min", "records[0].ms_per_step_min", false},
      {"/records/0/ms_per_step_max", "records[0].ms_per_step_max", false},
      {"/records/0/ms_per_step_cv", "records[0].ms_per_step_cv", false},
      {"/records/0/ms_runs/1", "records[0].ms_runs[1]", false},
      {"/records/0/load", "records[0].load", false},
      {"/records/0/primary_error", "records[0].primary_error", false},
      {"/records/0/primary_error_final", "records[0].primary_error_final", false},
      {"/records/0/ref_error_mm", "records[0].ref_error_mm", false},
      {"/records/0/trajectory_error_mm", "records[0].trajectory_error_mm", false},
      {"/records/0/errors/stretch_pct/rms", "records[0].errors.stretch_pct.rms", false},
      {"/records/0/errors_final/stretch_pct/max", "records[0].errors_final.stretch_pct.max", false},
      {"/scenes/0/particles", "scenes[0].particles", true},
      {"/scenes/0/steps", "scenes[0].steps", true},
      {"/scenes/0/average_from", "scenes[0].average_from", true},
      {"/scenes/0/size_m", "scenes[0].size_m", false},
      {"/references/0/substeps", "references[0].substeps", true},
      {"/references/0/threads", "references[0].threads", true},
      {"/references/0/seconds", "references[0].seconds", false},
      {"/references/0/step_change_mm", "references[0].step_change_mm", false},
      {"/references/0/error_change/stretch_pct/rms", "references[0].error_change.stretch_pct.rms", false},
      {"/shared_nothing/0/threads", "shared_nothing[0].threads", true},
      {"/shared_nothing/0/speedups/0", "shared_nothing[0].speedups[0]", false},
      {"/study/seconds", "study.seconds", false},
      {"/study/context/load_during", "study.context.load_during", false},
      {"/study/context/cores", "study.context.cores", true},
      {"/study/options/threads/0", "study.options.threads[0]", true},
      {"/study/options/repeats", "study.options.repeats", true},
      {"/study/options/budgets/0", "study.options.budgets[0]", true},
      {"/study/options/target_pct", "study.options.target_pct", false},
      {"/study/options/reference/substeps", "study.options.reference.substeps", true},
  };
  for (const Field& f : fields) {
    std::vector<json> bad = {-1, "1", json::object(), true};
    if (f.count) bad.insert(bad.end(), {0, 2.5, 1e30});
    for (const json& value : bad) {
      json edited = doc;
      edited[json::json_pointer(f.pointer)] = value;
      const std::string error = refusal(edited);
      EXPECT_EQ(error.rfind(std::string("a.json: ") + f.key + ": ", 0), 0u) << f.key << " = " << value << ": " << error;
    }
  }
}

TEST(StudyReportReader, RefusesTheIssuesCorruptedValues) {
  const json doc = report_json(sample_report());
  json threads = doc, substeps = doc, time = doc, hash = doc;
  threads["records"][0]["threads"] = 1e30;
  EXPECT_EQ(refusal(threads), "a.json: records[0].threads: 1e+30 is not an integer");
  substeps["records"][1]["substeps"] = 0;
  EXPECT_EQ(refusal(substeps), "a.json: records[1].substeps: 0 is out of range [1, 10000]");
  time["records"][0]["ms_per_step"] = -3.5;
  EXPECT_EQ(refusal(time), "a.json: records[0].ms_per_step: -3.5 is out of range [0, 1000000000000]");
  hash["records"][0]["state_hash"] = "not hex";
  EXPECT_EQ(refusal(hash), "a.json: records[0].state_hash: \"not hex\" is not 16 lower-case hex digits");
}

TEST(StudyReportReader, RefusesNamesThatAreNotTheStudys) {
  const json doc = report_json(sample_report());
  for (const auto& [pointer, value] : std::vector<std::pair<std::string, json>>{
           {"/records/0/solver", "gauss"}, {"/records/0/solver", "serial+chebyshev"}, {"/records/0/variant", "x"},
           {"/records/0/precision", "half"}, {"/records/0/scene", ""}, {"/records/0/scene", "a\nb"},
           {"/study/mode", "other"}, {"/study/options/shard", "3/2"}, {"/study/options/solvers/1", "x"}}) {
    json edited = doc;
    edited[json::json_pointer(pointer)] = value;
    EXPECT_NE(refusal(edited).find("a.json: "), std::string::npos) << pointer;
    EXPECT_NE(refusal(edited), "(no error)") << pointer;
  }
}

TEST(StudyReportReader, RefusesAReportNestedDeeperThanTheLimit) {
  // The depth of the issue's report: copying it as JSON overflowed the stack.
  const std::size_t depth = 150000;
  const std::string deep = std::string(depth, '[') + std::string(depth, ']');
  const std::string text = "{\"schema\": 3, \"study\": {\"context\": {\"cpu\": " + deep + "}}}";
  std::string path = "study.context.cpu";  // three objects, then arrays up to the 64th container
  for (int i = 3; i < 64; ++i) path += "[0]";
  EXPECT_EQ(error_of([&] { (void)parse_report(text, "deep.json"); }),
            "deep.json: " + path + ": arrays and objects nested more than 64 deep");
  // 64 deep is read.
  const std::string limit = std::string(kMaxJsonFileDepth, '[') + std::string(kMaxJsonFileDepth, ']');
  EXPECT_NO_THROW((void)parse_json_text(limit, "limit.json"));
  EXPECT_THROW((void)parse_json_text("[" + limit + "]", "limit.json"), Error);
}

TEST(StudyReportReader, RefusesWhatIsNotOneJsonDocument) {
  EXPECT_EQ(error_of([] { (void)parse_json_text("{\"a\": 1, \"b\": {\"c\": 2, \"c\": 3}}", "k.json"); }),
            "k.json: b.c: this key is given twice in the same object");
  EXPECT_EQ(error_of([] { (void)parse_json_text(std::string("{}\0garbage", 10), "n.json"); }),
            "n.json: not JSON (a NUL byte at line 1, column 3)");
  EXPECT_NE(error_of([] { (void)parse_json_text("{} {}", "t.json"); }).find("t.json: not JSON (parse error"),
            std::string::npos);
  EXPECT_NE(error_of([] { (void)parse_json_text("{\"a\": 1e400}", "o.json"); }).find("o.json: not JSON ("),
            std::string::npos);
  EXPECT_EQ(error_of([] { (void)report_from_json(json::array(), "x.json"); }),
            "x.json: (top): an array is not an object (not a pbd study report)");
  EXPECT_EQ(error_of([] { (void)report_from_json(json{{"schema", 2}}, "x.json"); }),
            "x.json: schema: 2, not 3 (not a pbd study report of schema 3)");
}

// A FIFO would block the read forever; a folder cannot be read as text: both are refused before anything is read.
TEST(StudyReportReader, RefusesFilesThatAreNotRegularFiles) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("pbd_report_reader_" +
                                                                              std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string fifo = (dir / "fifo.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(error_of([&] { (void)read_report(fifo); }),
            fifo + ": cannot read the study report (not a regular file)");
  EXPECT_EQ(error_of([&] { (void)read_report(dir.string()); }),
            dir.string() + ": cannot read the study report (not a regular file)");
  EXPECT_EQ(error_of([&] { (void)read_report((dir / "missing.json").string()); }),
            (dir / "missing.json").string() + ": cannot read the study report (No such file or directory)");
  const std::string empty = (dir / "empty.json").string();
  std::ofstream{empty};
  EXPECT_EQ(error_of([&] { (void)read_report(empty); }), empty + ": the study report is empty (0 bytes)");
  const std::string good = (dir / "good.json").string();
  std::ofstream(good) << report_json(sample_report()).dump();
  EXPECT_EQ(read_report(good).records.size(), 2u);
  std::filesystem::remove_all(dir);
}

TEST(StudyMerge, RefusesAsManyFileNamesAsReportsOnly) {
  EXPECT_EQ(error_of([] { (void)merge_reports({sample_report()}, {}); }), "merge: 1 reports but 0 file names");
}

}  // namespace
}  // namespace pbd::cli
