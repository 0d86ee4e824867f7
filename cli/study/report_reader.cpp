#include "report_reader.hpp"

#include "json_file.hpp"
#include "pbd/error.hpp"
#include "pbd/solver.hpp"
#include "report_fields.hpp"
#include "scene_variants.hpp"

#include <cstdio>
#include <limits>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// Bounds of what no study comes near, for the values the study's options do not bound: counts of a scene (the
// scene parser's own limits are far below), times in ms or s, loads in runnable threads, ratios.
constexpr long long kMaxCount = 1'000'000'000'000;
constexpr double kMaxTime = 1e12;
constexpr double kMaxLoad = 1e9;
constexpr double kMaxRatio = 1e9;
constexpr double kMaxMagnitude = std::numeric_limits<double>::max();

int integer(const ReportFields& f, const std::string& key, long long lo, long long hi) {
  return int(f.integer(key, lo, hi));
}

// A solver of the study: serial, serial-colored, colored, jacobi or block, any but serial with "+chebyshev".
bool study_solver(const std::string& name) {
  const std::string suffix = "+chebyshev";
  const bool chebyshev = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(),
                                                                     suffix) == 0;
  const auto s = parse_solver(chebyshev ? name.substr(0, name.size() - suffix.size()) : name);
  return s && !(chebyshev && *s == Solver::serial);
}
std::string not_a_solver(const json& v) {
  return describe_value(v) + " is not a solver of the study (" + solver_names() + ", any but serial with +chebyshev)";
}

std::string solver(const ReportFields& f, const std::string& key) {
  const std::string name = f.name(key);
  if (!study_solver(name)) f.fail(key, not_a_solver(f.value(key)));
  return name;
}

// Measures by name, each {"rms", "max"}: errors (finite, at least 0, or null where it diverged).
Errors errors(const ReportFields& f, const std::string& key) {
  const ReportFields measures = f.object(key);
  Errors out;
  for (const auto& [name, v] : f.value(key).items()) {
    if (name.empty()) measures.fail(name, "a measure with no name");
    const ReportFields e = measures.object(name);
    out[name] = {e.error("rms"), e.error("max")};
  }
  return out;
}

// "I/N" with 1 <= I <= N, or null (a whole run).
void check_shard(const ReportFields& options) {
  if (!options.has("shard") || options.value("shard").is_null()) return;
  int i = 0, n = 0;
  char tail = 0;
  const std::string text = options.name("shard");
  if (std::sscanf(text.c_str(), "%d/%d%c", &i, &n, &tail) != 2 || i < 1 || i > n)
    options.fail("shard", describe_value(options.value("shard")) + " is not I/N with 1 <= I <= N");
}

// What the report's code reads of "study": its mode, context (loads, cores) and options.
void check_study(const ReportFields& study) {
  const std::string mode = study.has("mode") ? study.one_of("mode", {"study", "scaling"}) : "study";
  if (study.has("seconds")) study.number("seconds", 0.0, kMaxTime);
  const ReportFields context = study.object("context");
  for (const char* key : {"load_before", "load_during", "load_during_max"})
    if (context.has(key)) context.number(key, 0.0, kMaxLoad);
  if (context.has("cores") && !context.value("cores").is_null()) context.integer("cores", 1, kMaxCount);
  if (context.has("mixed_machines")) context.boolean("mixed_machines");
  const ReportFields options = study.object("options");
  options.names("scenes");
  const std::vector<std::string> solvers = options.names("solvers");
  for (std::size_t i = 0; i < solvers.size(); ++i)
    if (!study_solver(solvers[i])) options.fail("solvers[" + std::to_string(i) + "]", not_a_solver(solvers[i]));
  options.integers("threads", 1, kMaxStudyThreads, 1);
  options.one_of("precision", {"float", "double"});
  options.integer("repeats", 1, kMaxRepeats);
  if (!options.value("steps").is_string() || options.value("steps") != "scene") options.integer("steps", 1, kMaxSteps);
  options.boolean("quick");
  options.names("variants");
  if (options.has("target_pct")) options.number("target_pct", 1e-9, 1e9);
  check_shard(options);
  if (mode == "scaling") {
    const ReportFields split = options.object("split");
    split.integer("substeps", 1, kMaxSubsteps);
    split.integer("iterations", 1, kMaxIterations);
    return;
  }
  options.integers("budgets", 1, kMaxStudyBudget, 1);
  const ReportFields reference = options.object("reference");
  solver(reference, "solver");
  reference.integer("substeps", 1, kMaxSubsteps);
  reference.integer("iterations", 1, kMaxIterations);
  reference.integer("max_budget", 1, kMaxReferenceBudget);
  reference.number("max_seconds", 0.0, kMaxReferenceSeconds);
}

SceneInfo scene_info(const ReportFields& s) {
  SceneInfo i;
  i.name = s.name("name");
  i.particles = std::size_t(s.integer("particles", 1, kMaxCount));
  i.constraints = std::size_t(s.integer("constraints", 0, kMaxCount));
  i.steps = integer(s, "steps", 1, kMaxSteps);
  i.size_m = s.number("size_m", 0.0, kMaxMagnitude);
  // A scene with no constraint has no primary measure ("").
  i.primary_error = s.value("primary_error") == "" ? "" : s.name("primary_error");
  i.family = s.name_or_null("family");
  i.measures = s.names("measures");
  i.base = s.name("base");
  i.variant = s.one_of("variant", variant_names());
  i.known_answer = s.name_or_null("known_answer");
  i.average_from = integer(s, "average_from", 1, i.steps);
  return i;
}

Reference reference(const ReportFields& r) {
  Reference ref;
  ref.scene = r.name("scene");
  ref.substeps = integer(r, "substeps", 1, kMaxSubsteps);
  ref.iterations = integer(r, "iterations", 1, kMaxIterations);
  ref.steps = integer(r, "steps", 1, kMaxSteps);
  ref.solver = solver(r, "solver");
  ref.threads = integer(r, "threads", 1, kMaxStudyThreads);
  ref.seconds = r.number("seconds", 0.0, kMaxTime);
  ref.errors = errors(r, "errors");
  ref.errors_final = errors(r, "errors_final");
  ref.step_change_mm = r.error("step_change_mm");
  ref.trajectory_change_mm = r.error("trajectory_change_mm");
  ref.error_change = errors(r, "error_change");
  ref.capped = r.boolean("capped");
  ref.tried = r.names("tried");
  return ref;
}

// The 16 hex digits the report writes.
std::uint64_t state_hash(const ReportFields& j) {
  const std::string text = j.name("state_hash");
  std::uint64_t h = 0;
  bool hex = text.size() == 16;
  for (char c : text) {
    const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    hex = hex && digit >= 0;
    h = h * 16 + std::uint64_t(digit < 0 ? 0 : digit);
  }
  if (!hex) j.fail("state_hash", describe_value(j.value("state_hash")) + " is not 16 lower-case hex digits");
  return h;
}

Record record(const ReportFields& j) {
  Record r;
  r.scene = j.name("scene");
  r.solver = solver(j, "solver");
  r.threads = integer(j, "threads", 1, kMaxStudyThreads);
  r.substeps = integer(j, "substeps", 1, kMaxSubsteps);
  r.iterations = integer(j, "iterations", 1, kMaxIterations);
  r.steps = integer(j, "steps", 1, kMaxSteps);
  r.precision = j.one_of("precision", {"float", "double"});
  r.repeats = integer(j, "repeats", 1, kMaxRepeats);
  r.ms = j.numbers("ms_runs", 0.0, kMaxTime, 1);
  if (r.ms.size() > std::size_t(r.repeats))  // a long run is timed fewer times than asked, never more
    j.fail("ms_runs", std::to_string(r.ms.size()) + " timed runs, more than its " + std::to_string(r.repeats) +
                          " repeats");
  r.ms_per_step = j.number("ms_per_step", 0.0, kMaxTime);
  r.ms_per_step_min = j.number("ms_per_step_min", 0.0, kMaxTime);
  r.ms_per_step_max = j.number("ms_per_step_max", 0.0, kMaxTime);
  r.ms_per_step_cv = j.number("ms_per_step_cv", 0.0, kMaxRatio);
  r.particles = std::size_t(j.integer("particles", 1, kMaxCount));
  r.constraints = std::size_t(j.integer("constraints", 0, kMaxCount));
  r.colors = std::size_t(j.integer("colors", 0, kMaxCount));
  r.variant = j.one_of("variant", variant_names());
  r.timing_steps = integer(j, "timing_steps", 1, r.steps);
  r.errors = errors(j, "errors");
  r.errors_final = errors(j, "errors_final");
  r.primary_error = j.error("primary_error");
  r.primary_error_final = j.error("primary_error_final");
  r.settle_motion_mm = j.number_or_null("settle_motion_mm", 0.0, kMaxMagnitude);
  r.settled = j.boolean_or_null("settled");
  // Measured against a reference (main mode): all three, each null where it diverged.
  if (!j.value("trajectory_error_mm").is_null() || !j.value("ref_error_mm").is_null()) {
    r.ref_error_mm = j.error("ref_error_mm");
    r.ref_error_max_mm = j.error("ref_error_max_mm");
    r.trajectory_error_mm = j.error("trajectory_error_mm");
  }
  r.energy_drift = j.number_or_null("energy_drift", -kMaxMagnitude, kMaxMagnitude);
  r.state_hash = state_hash(j);
  r.repeatable = j.boolean("repeatable");
  r.load = j.number("load", 0.0, kMaxLoad);
  r.busy = j.boolean("busy");
  return r;
}

SharedNothing shared_nothing(const ReportFields& s) {
  // One speed-up per round: a run has at least one.
  return {s.name("scene"), integer(s, "threads", 2, kMaxStudyThreads), s.numbers("speedups", 0.0, kMaxRatio, 1)};
}

}  // namespace

Report report_from_json(const json& doc, const std::string& source) {
  const ReportFields top(doc, source, "");
  if (!top.has("schema") || top.value("schema") != 3)
    top.fail("schema", (top.has("schema") ? describe_value(top.value("schema")) : std::string("missing")) +
                           ", not 3 (not a pbd study report of schema 3)");
  Report report;
  check_study(top.object("study"));
  report.study = doc.at("study");
  for (const ReportFields& s : top.objects("scenes")) report.scenes.push_back(scene_info(s));
  for (const ReportFields& r : top.objects("references")) report.references.push_back(reference(r));
  for (const ReportFields& r : top.objects("records")) report.records.push_back(record(r));
  for (const ReportFields& s : top.objects("shared_nothing")) report.shared_nothing.push_back(shared_nothing(s));
  finish(report);
  return report;
}

Report parse_report(const std::string& text, const std::string& source) {
  return report_from_json(parse_json_text(text, source), source);
}

Report read_report(const std::string& file) {
  return report_from_json(read_json_file(file, "study report", kMaxReportBytes), file);
}

}  // namespace pbd::cli
