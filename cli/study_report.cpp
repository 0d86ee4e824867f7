#include "study_report.hpp"

#include "pbd/error.hpp"
#include "load_monitor.hpp"
#include "scene_variants.hpp"
#include "study_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <ostream>
#include <set>

namespace pbd::cli {

double Record::ns_per_projection() const {
  const double projections = double(constraints) * substeps * iterations;
  return projections > 0.0 ? ms_per_step * 1e6 / projections : 0.0;
}

namespace {

using json = nlohmann::json;

std::string fmt(double v, const char* f = "%.3g") {
  if (!std::isfinite(v)) return "inf";
  char s[32];
  std::snprintf(s, sizeof s, f, v);
  return s;
}

std::string hex(std::uint64_t h) {
  char s[19];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }
std::optional<double> number_or_none(const json& v) {
  return v.is_null() ? std::nullopt : std::optional<double>(v.get<double>());
}

// JSON numbers cannot be infinite: a diverged error is written as null... and read back as infinity.
json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
double finite_back(const json& v) { return v.is_null() ? INFINITY : v.get<double>(); }

json errors_json(const Errors& e) {
  json out = json::object();
  for (const auto& [name, v] : e) out[name] = {{"rms", finite(v.rms)}, {"max", finite(v.max)}};
  return out;
}
Errors errors_back(const json& j) {
  Errors out;
  for (const auto& [name, v] : j.items()) out[name] = {finite_back(v.at("rms")), finite_back(v.at("max"))};
  return out;
}

const SceneInfo* find_scene(const Report& r, const std::string& name) {
  for (const SceneInfo& s : r.scenes)
    if (s.name == name) return &s;
  return nullptr;
}


// Whether a measure is in % (the headline's target applies to it): stretch_pct, area_pct, volume_pct, ...
bool percent_measure(const std::string& m) { return m.size() > 4 && m.compare(m.size() - 4, 4, "_pct") == 0; }

std::vector<TimeToTarget> times_to_target(const Report& report) {
  std::vector<TimeToTarget> out;
  const double target = report.study.value("options", json::object()).value("target_pct", 1.0);
  for (const Record& r : report.records) {
    const SceneInfo* scene = find_scene(report, r.scene);
    if (!scene || !percent_measure(scene->primary_error)) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const TimeToTarget& t) {
      return t.scene == r.scene && t.solver == r.solver && t.threads == r.threads;
    });
    const bool reached = r.primary_error <= target;
    if (it == out.end()) {
      out.push_back({r.scene, r.base(), r.variant, r.solver, r.threads, scene->primary_error, target, reached,
                     r.substeps, r.iterations, r.ms_per_step, r.primary_error});
      continue;
    }
    TimeToTarget& t = *it;
    const bool better = reached ? !t.reached || r.ms_per_step < t.ms_per_step
                                : !t.reached && r.primary_error < t.primary_error;
    if (better) {
      t.reached = reached;
      t.substeps = r.substeps;
      t.iterations = r.iterations;
      t.ms_per_step = r.ms_per_step;
      t.primary_error = r.primary_error;
    }
  }
  return out;
}

}  // namespace

void check_reference(Reference& ref, const std::vector<Record>& records, bool by_reference) {
  ref.failures.clear();
  double step = INFINITY, trajectory = INFINITY;
  std::map<std::string, double> smallest;
  for (const Record& r : records) {
    if (r.base() != ref.scene) continue;
    if (r.ref_error_mm) step = std::min(step, *r.ref_error_mm);
    if (r.trajectory_error_mm) trajectory = std::min(trajectory, *r.trajectory_error_mm);
    for (const auto& [m, v] : r.errors) {
      const auto it = smallest.find(m);
      smallest[m] = it == smallest.end() ? v.rms : std::min(it->second, v.rms);
    }
  }
  char line[256];
  auto compare = [&](const std::string& what, double change, double error, const char* unit) {
    if (!std::isfinite(error)) return;  // nothing compared with it
    if (change <= kReferenceMargin * error) return;
    std::snprintf(line, sizeof line, "%s changes by %.3g %s at half its budget, more than a tenth of the smallest "
                  "error it is compared with (%.3g %s)", what.c_str(), change, unit, error, unit);
    ref.failures.push_back(line);
  };
  compare("one step", ref.step_change_mm, step, "mm");
  ref.step_converged = ref.failures.empty();
  compare("the run's end", ref.trajectory_change_mm, trajectory, "mm");
  for (const auto& [m, change] : ref.error_change) {
    if (by_reference) break;
    const auto it = smallest.find(m);
    const std::string unit = m.size() > 4 && m.compare(m.size() - 4, 4, "_pct") == 0   ? "%"
                             : m.size() > 3 && m.compare(m.size() - 3, 3, "_mm") == 0  ? "mm"
                             : m.size() > 4 && m.compare(m.size() - 4, 4, "_rad") == 0 ? "rad"
                                                                                       : "";
    if (it != smallest.end() && it->second > 0.0) compare(m + " (run average)", change.rms, it->second, unit.c_str());
  }
  ref.converged = ref.failures.empty();
}

void finish(Report& report) {
  std::vector<Record>& records = report.records;
  // A scene judged against its reference takes its primary error from it (NaN where none was measured).
  for (Record& r : records) {
    const SceneInfo* scene = find_scene(report, r.scene);
    if (!scene || scene->primary_error != kReferenceMeasure) continue;
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    r.primary_error = r.ref_error_mm.value_or(kNone);
    r.primary_error_final = r.trajectory_error_mm.value_or(kNone);
  }
  // Pareto front per scene over (median ms per step, primary error).
  for (Record& r : records) {
    r.pareto = std::none_of(records.begin(), records.end(), [&](const Record& o) {
      return o.scene == r.scene && o.ms_per_step <= r.ms_per_step && o.primary_error <= r.primary_error &&
             (o.ms_per_step < r.ms_per_step || o.primary_error < r.primary_error);
    });
  }
  // Best split per (scene, solver, threads, budget).
  report.best_splits.clear();
  std::map<std::tuple<std::string, std::string, int, int>, std::size_t> best;
  std::vector<std::tuple<std::string, std::string, int, int>> order;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    const auto key = std::make_tuple(r.scene, r.solver, r.threads, r.budget());
    const auto it = best.find(key);
    if (it == best.end()) {
      best[key] = i;
      order.push_back(key);
    } else {
      const Record& b = records[it->second];
      if (r.primary_error < b.primary_error || (r.primary_error == b.primary_error && r.ms_per_step < b.ms_per_step))
        it->second = i;
    }
  }
  for (const auto& key : order) {
    const Record& r = records[best[key]];
    report.best_splits.push_back({r.scene, r.solver, r.threads, r.budget(), r.substeps, r.iterations, r.ms_per_step,
                                  r.primary_error});
  }
  // Dominance of serial by each parallel solver at its most threads.
  report.dominance.clear();
  for (const SceneInfo& scene : report.scenes) {
    std::map<std::string, int> most;
    std::vector<std::string> solvers;
    for (const Record& r : records)
      if (r.scene == scene.name && r.solver != "serial") {
        if (!most.count(r.solver)) solvers.push_back(r.solver);
        most[r.solver] = std::max(most[r.solver], r.threads);
      }
    for (const std::string& solver : solvers) {
      Dominance d{scene.name, solver, scene.primary_error, most[solver], 0, {}};
      for (const Record& s : records) {
        if (s.scene != scene.name || s.solver != "serial") continue;
        ++d.serial_points;
        const bool dominated = std::any_of(records.begin(), records.end(), [&](const Record& c) {
          return c.scene == s.scene && c.solver == solver && c.threads == d.threads && c.ms_per_step < s.ms_per_step &&
                 c.primary_error <= s.primary_error;
        });
        if (!dominated) d.undominated.push_back(s.split());
      }
      if (d.serial_points) report.dominance.push_back(d);
    }
  }
  // Strong scaling: speed-up over the same solver on 1 thread at the same split, round by round.
  report.strong.clear();
  if (report.study.value("mode", "study") == "scaling") {
    for (const Record& r : records) {
      const auto one = std::find_if(records.begin(), records.end(), [&](const Record& o) {
        return o.scene == r.scene && o.solver == r.solver && o.threads == 1 && o.substeps == r.substeps &&
               o.iterations == r.iterations;
      });
      if (one == records.end()) continue;
      std::vector<double> ratios;
      for (std::size_t k = 0; k < std::min(one->ms.size(), r.ms.size()); ++k) ratios.push_back(one->ms[k] / r.ms[k]);
      if (ratios.empty()) continue;
      const auto [lo, hi] = std::minmax_element(ratios.begin(), ratios.end());
      report.strong.push_back({r.scene, r.solver, r.particles, r.threads, r.ms_per_step, r.ms_per_step_min,
                               r.ms_per_step_max, median(ratios), *lo, *hi});
    }
  }
  for (Reference& ref : report.references) {
    const SceneInfo* scene = find_scene(report, ref.scene);
    check_reference(ref, records, scene && scene->primary_error == kReferenceMeasure);
  }
  report.time_to_target.clear();
  if (report.study.value("mode", "study") != "scaling") report.time_to_target = times_to_target(report);
  // Warnings.
  json warnings = json::array();
  for (const Reference& ref : report.references)
    if (!ref.converged)
      warnings.push_back(ref.scene + ": THE REFERENCE IS NOT CONVERGED (" + ref.solver + " " +
                         std::to_string(ref.substeps) + "x" + std::to_string(ref.iterations) +
                         (ref.capped ? ", and the study could not raise its budget further" : "") + "): " +
                         (ref.failures.empty() ? std::string("?") : ref.failures.front()) +
                         (ref.step_converged ? "; its one step is converged (ref_mm holds), traj_mm of its scene is "
                                               "bounded by the reference's own error"
                                             : "; ref_mm and traj_mm of its scene are bounded by the reference's own "
                                               "error"));
  for (const SceneInfo& scene : report.scenes) {
    int moving = 0, points = 0;
    std::string splits;
    for (const Record& r : records)
      if (r.scene == scene.name && r.settled) {
        ++points;
        if (*r.settled) continue;
        if (moving++ < 6) splits += (splits.empty() ? "" : ", ") + r.solver + " " + r.split();
      }
    if (moving)
      warnings.push_back(scene.name + ": " + std::to_string(moving) + " of " + std::to_string(points) +
                         " points had not settled at the end (they moved more than 1 mm RMS over the steps averaged; e.g. " + splits +
                         "): their error is not that of a state at rest");
  }
  const json& context = report.study["context"];
  // null for a report merged from machines of other core counts (merge_reports)
  const json cores = context.value("cores", json(nullptr));
  const std::string cores_text = cores.is_number() ? cores.dump() + " cores" : "mixed machines";
  const double before = context.value("load_before", 0.0), during = context.value("load_during", 0.0);
  if (before > kBusyLoad || during > kBusyLoad) {
    char w[320];
    std::snprintf(w, sizeof w, "the machine was busy: other processes kept %.2f threads runnable before the study "
                  "and %.2f on average during it (%s); timings are not trustworthy", before, during,
                  cores_text.c_str());
    warnings.push_back(w);
  }
  const auto busy = std::count_if(records.begin(), records.end(), [](const Record& r) { return r.busy; });
  if (busy > 0) {
    char w[256];
    std::snprintf(w, sizeof w, "%ld of %zu points are marked busy (their runs' CV above %.0f%% or other processes "
                  "runnable above %.1f threads)", long(busy), records.size(), 100 * kBusyCv, kBusyLoad);
    warnings.push_back(w);
  }
  for (const Record& r : records)
    if (!r.repeatable) warnings.push_back(r.scene + " " + r.solver + " " + std::to_string(r.threads) + " threads " +
                                          r.split() + ": the runs ended in different states");
  report.study["warnings"] = warnings;
  report.study["busy"] = !warnings.empty();
}

json report_json(const Report& report) {
  json doc = {{"schema", 3}, {"study", report.study}};
  json& scenes = doc["scenes"] = json::array();
  for (const SceneInfo& s : report.scenes)
    scenes.push_back({{"name", s.name}, {"particles", s.particles}, {"constraints", s.constraints},
                      {"steps", s.steps}, {"size_m", s.size_m}, {"primary_error", s.primary_error},
                      {"family", s.family.empty() ? json(nullptr) : json(s.family)}, {"measures", s.measures},
                      {"base", s.base}, {"variant", s.variant},
                      {"known_answer", s.known_answer.empty() ? json(nullptr) : json(s.known_answer)},
                      {"average_from", s.average_from}});
  // Every error measure's label and unit, as the constraint types declare them (plot_study.py labels its axes so).
  json& measures = doc["measures"] = json::object();
  for (const NamedMeasure& m : violation_measures())
    measures[m.measure.key] = {{"type", m.type}, {"label", m.measure.label}, {"unit", m.measure.unit}};
  for (const ExtraMeasure& m : known_answer_measures())
    measures[m.key] = {{"type", nullptr}, {"label", m.label}, {"unit", m.unit}};
  measures[kReferenceMeasure] = {{"type", nullptr}, {"label", "one-step distance from the converged reference"},
                                 {"unit", "mm"}};
  json& refs = doc["references"] = json::array();
  for (const Reference& r : report.references)
    refs.push_back({{"scene", r.scene}, {"solver", r.solver}, {"precision", "double"}, {"threads", r.threads},
                    {"substeps", r.substeps}, {"iterations", r.iterations}, {"steps", r.steps},
                    {"seconds", r.seconds}, {"errors", errors_json(r.errors)},
                    {"errors_final", errors_json(r.errors_final)}, {"step_change_mm", finite(r.step_change_mm)},
                    {"trajectory_change_mm", finite(r.trajectory_change_mm)},
                    {"error_change", errors_json(r.error_change)}, {"converged", r.converged},
                    {"step_converged", r.step_converged}, {"failures", r.failures}, {"capped", r.capped},
                    {"tried", r.tried}});
  json& records = doc["records"] = json::array();
  for (const Record& r : report.records)
    records.push_back({{"scene", r.scene}, {"solver", r.solver}, {"threads", r.threads}, {"budget", r.budget()},
                       {"substeps", r.substeps}, {"iterations", r.iterations}, {"steps", r.steps},
                       {"precision", r.precision}, {"repeats", r.repeats}, {"ms_runs", r.ms},
                       {"ms_per_step", r.ms_per_step}, {"ms_per_step_min", r.ms_per_step_min},
                       {"ms_per_step_max", r.ms_per_step_max}, {"ms_per_step_cv", r.ms_per_step_cv},
                       {"ns_per_projection", r.ns_per_projection()}, {"particles", r.particles},
                       {"constraints", r.constraints}, {"colors", r.colors}, {"variant", r.variant},
                       {"timing_steps", r.timing_steps}, {"errors", errors_json(r.errors)},
                       {"errors_final", errors_json(r.errors_final)}, {"primary_error", finite(r.primary_error)},
                       {"primary_error_final", finite(r.primary_error_final)},
                       {"settle_motion_mm", optional_number(r.settle_motion_mm)},
                       {"settled", r.settled ? json(*r.settled) : json(nullptr)},
                       {"ref_error_mm", r.ref_error_mm ? finite(*r.ref_error_mm) : json(nullptr)},
                       {"ref_error_max_mm", r.ref_error_max_mm ? finite(*r.ref_error_max_mm) : json(nullptr)},
                       {"trajectory_error_mm", r.trajectory_error_mm ? finite(*r.trajectory_error_mm) : json(nullptr)},
                       {"energy_drift", optional_number(r.energy_drift)}, {"state_hash", hex(r.state_hash)},
                       {"repeatable", r.repeatable}, {"load", r.load}, {"busy", r.busy}, {"pareto", r.pareto}});
  json& best = doc["best_splits"] = json::array();
  for (const BestSplit& b : report.best_splits)
    best.push_back({{"scene", b.scene}, {"solver", b.solver}, {"threads", b.threads}, {"budget", b.budget},
                    {"substeps", b.substeps}, {"iterations", b.iterations}, {"ms_per_step", b.ms_per_step},
                    {"primary_error", finite(b.primary_error)}});
  json& dom = doc["dominance"] = json::array();
  for (const Dominance& d : report.dominance)
    dom.push_back({{"scene", d.scene}, {"solver", d.solver}, {"threads", d.threads}, {"measure", d.measure},
                   {"serial_points", d.serial_points}, {"dominated", d.serial_points - int(d.undominated.size())},
                   {"undominated", d.undominated}});
  json& ttt = doc["time_to_target"] = json::array();
  for (const TimeToTarget& t : report.time_to_target)
    ttt.push_back({{"scene", t.scene}, {"base", t.base}, {"variant", t.variant}, {"solver", t.solver},
                   {"threads", t.threads}, {"measure", t.measure}, {"target", t.target}, {"reached", t.reached},
                   {"substeps", t.substeps}, {"iterations", t.iterations}, {"ms_per_step", t.ms_per_step},
                   {"primary_error", finite(t.primary_error)}});
  json& sn = doc["shared_nothing"] = json::array();
  for (const SharedNothing& s : report.shared_nothing) {
    const auto [lo, hi] = std::minmax_element(s.speedups.begin(), s.speedups.end());
    sn.push_back({{"scene", s.scene}, {"threads", s.threads}, {"speedups", s.speedups},
                  {"speedup", median(s.speedups)}, {"speedup_min", *lo}, {"speedup_max", *hi}});
  }
  if (report.study.value("mode", "study") == "scaling") {
    json strong = json::array(), size = json::array();
    for (const StrongScaling& s : report.strong)
      strong.push_back({{"scene", s.scene}, {"particles", s.particles}, {"solver", s.solver}, {"threads", s.threads},
                        {"ms_per_step", s.ms_per_step}, {"ms_per_step_min", s.ms_per_step_min},
                        {"ms_per_step_max", s.ms_per_step_max}, {"speedup", s.speedup},
                        {"speedup_min", s.speedup_min}, {"speedup_max", s.speedup_max}});
    for (const Record& r : report.records)
      size.push_back({{"scene", r.scene}, {"particles", r.particles}, {"constraints", r.constraints},
                      {"solver", r.solver}, {"threads", r.threads}, {"ms_per_step", r.ms_per_step},
                      {"ns_per_projection", r.ns_per_projection()}, {"primary_error", finite(r.primary_error)}});
    json split = report.study["options"].value("split", json::object());
    doc["scaling"] = {{"split", split}, {"strong", strong}, {"size", size}};
  }
  return doc;
}

Report report_from_json(const json& doc, const std::string& source) {
  try {
    if (doc.value("schema", 0) != 3) throw Error(source + ": not a pbd study report of schema 3");
    Report report;
    report.study = doc.at("study");
    for (const json& s : doc.at("scenes")) {
      SceneInfo i;
      i.name = s.at("name");
      i.particles = s.at("particles");
      i.constraints = s.at("constraints");
      i.steps = s.at("steps");
      i.size_m = s.at("size_m");
      i.primary_error = s.at("primary_error");
      i.family = s.at("family").is_null() ? "" : s.at("family").get<std::string>();
      i.measures = s.at("measures").get<std::vector<std::string>>();
      i.base = s.at("base");
      i.variant = s.at("variant");
      i.known_answer = s.at("known_answer").is_null() ? "" : s.at("known_answer").get<std::string>();
      i.average_from = s.at("average_from");
      report.scenes.push_back(i);
    }
    for (const json& r : doc.at("references")) {
      Reference ref;
      ref.scene = r.at("scene");
      ref.substeps = r.at("substeps");
      ref.iterations = r.at("iterations");
      ref.steps = r.at("steps");
      ref.solver = r.at("solver");
      ref.threads = r.at("threads");
      ref.seconds = r.at("seconds");
      ref.errors = errors_back(r.at("errors"));
      ref.errors_final = errors_back(r.at("errors_final"));
      ref.step_change_mm = finite_back(r.at("step_change_mm"));
      ref.trajectory_change_mm = finite_back(r.at("trajectory_change_mm"));
      ref.error_change = errors_back(r.at("error_change"));
      ref.capped = r.at("capped");
      ref.tried = r.at("tried").get<std::vector<std::string>>();
      report.references.push_back(std::move(ref));
    }
    for (const json& j : doc.at("records")) {
      Record r;
      r.scene = j.at("scene");
      r.solver = j.at("solver");
      r.threads = j.at("threads");
      r.substeps = j.at("substeps");
      r.iterations = j.at("iterations");
      r.steps = j.at("steps");
      r.precision = j.at("precision");
      r.repeats = j.at("repeats");
      r.ms = j.at("ms_runs").get<std::vector<double>>();
      r.ms_per_step = j.at("ms_per_step");
      r.ms_per_step_min = j.at("ms_per_step_min");
      r.ms_per_step_max = j.at("ms_per_step_max");
      r.ms_per_step_cv = j.at("ms_per_step_cv");
      r.particles = j.at("particles");
      r.constraints = j.at("constraints");
      r.colors = j.at("colors");
      r.variant = j.at("variant");
      r.timing_steps = j.at("timing_steps");
      r.errors = errors_back(j.at("errors"));
      r.errors_final = errors_back(j.at("errors_final"));
      r.primary_error = finite_back(j.at("primary_error"));
      r.primary_error_final = finite_back(j.at("primary_error_final"));
      r.settle_motion_mm = number_or_none(j.at("settle_motion_mm"));
      if (!j.at("settled").is_null()) r.settled = j.at("settled").get<bool>();
      if (!j.at("trajectory_error_mm").is_null() || !j.at("ref_error_mm").is_null()) {
        r.ref_error_mm = finite_back(j.at("ref_error_mm"));
        r.ref_error_max_mm = finite_back(j.at("ref_error_max_mm"));
        r.trajectory_error_mm = finite_back(j.at("trajectory_error_mm"));
      }
      r.energy_drift = number_or_none(j.at("energy_drift"));
      r.state_hash = std::stoull(j.at("state_hash").get<std::string>(), nullptr, 16);
      r.repeatable = j.at("repeatable");
      r.load = j.at("load");
      r.busy = j.at("busy");
      report.records.push_back(std::move(r));
    }
    for (const json& s : doc.at("shared_nothing"))
      report.shared_nothing.push_back({s.at("scene"), s.at("threads"), s.at("speedups").get<std::vector<double>>()});
    finish(report);
    return report;
  } catch (const json::exception& e) {
    throw Error(source + ": not a complete pbd study report (" + e.what() + ")");
  }
}

namespace {

// A field of a part's report, by its path from "study" ("git_commit", "context/cpu"); null when it is missing.
json field(const Report& r, const std::string& path) {
  const json::json_pointer pointer("/" + path);
  return r.study.contains(pointer) ? r.study.at(pointer) : json(nullptr);
}

// "study.context.cpu is \"X\", a.json's is \"Y\"" when the part's field differs from the first part's.
void same_field(const Report& part, const std::string& source, const Report& first, const std::string& first_source,
                const std::string& path, const std::string& why) {
  const json a = field(part, path), b = field(first, path);
  if (a == b) return;
  std::string name = "study." + path;
  std::replace(name.begin(), name.end(), '/', '.');
  throw Error(source + ": " + name + " is " + a.dump() + ", " + first_source + "'s is " + b.dump() + " (" + why + ")");
}

// "I/N" of a part's options (1 of 1 for a whole run).
std::pair<int, int> shard_of(const json& options, const std::string& source) {
  const json shard = options.value("shard", json(nullptr));
  if (shard.is_null()) return {1, 1};
  int i = 0, n = 0;
  char tail = 0;
  if (!shard.is_string() || std::sscanf(shard.get<std::string>().c_str(), "%d/%d%c", &i, &n, &tail) != 2 || i < 1 ||
      i > n)
    throw Error(source + ": study.options.shard is " + shard.dump() + ", not I/N");
  return {i, n};
}

// The parts' shards must be 1..N of one N, each once.
void check_shards(const std::vector<Report>& parts, const std::vector<std::string>& sources) {
  std::map<int, std::string> seen;  // shard → the file that holds it
  const int n = shard_of(parts.front().study.at("options"), sources.front()).second;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const auto [i, of] = shard_of(parts[p].study.at("options"), sources[p]);
    const std::string name = of == 1 ? std::string("(whole run)") : std::to_string(i) + "/" + std::to_string(of);
    if (of != n)
      throw Error(sources[p] + ": study.options.shard is " + name + ", " + sources.front() + "'s is of " +
                  std::to_string(n) + " (the shards of one study split it into the same number of parts)");
    if (const auto it = seen.find(i); it != seen.end())
      throw Error(sources[p] + ": shard " + name + " is given twice (also " + it->second + ")");
    seen[i] = sources[p];
  }
  std::string missing;
  for (int i = 1; i <= n; ++i)
    if (!seen.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(n);
  if (!missing.empty())
    throw Error("the shards are incomplete: " + std::to_string(seen.size()) + " of " + std::to_string(n) +
                " given, missing " + missing + " (study.options.shard of each file)");
}

// Each machine the parts ran on (CPU and cores), with its hosts and files.
json machines_of(const std::vector<Report>& parts, const std::vector<std::string>& sources) {
  json machines = json::array();
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const json cpu = field(parts[p], "context/cpu"), cores = field(parts[p], "context/cores");
    const json host = field(parts[p], "context/host");
    auto it = std::find_if(machines.begin(), machines.end(),
                           [&](const json& m) { return m["cpu"] == cpu && m["cores"] == cores; });
    if (it == machines.end()) {
      machines.push_back({{"cpu", cpu}, {"cores", cores}, {"hosts", json::array()}, {"reports", json::array()}});
      it = machines.end() - 1;
    }
    if (std::find((*it)["hosts"].begin(), (*it)["hosts"].end(), host) == (*it)["hosts"].end())
      (*it)["hosts"].push_back(host);
    (*it)["reports"].push_back(sources[p]);
  }
  return machines;
}

}  // namespace

Report merge_reports(const std::vector<Report>& parts, const std::vector<std::string>& sources,
                     const MergeRules& rules) {
  if (parts.empty()) throw Error("merge: no reports given");
  Report out;
  out.study = parts.front().study;
  json options = out.study.at("options");
  options.erase("shard");
  double seconds = 0.0;
  const std::string& first = sources.front();
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Report& part = parts[p];
    const std::string& source = sources[p];
    if (part.study.value("mode", "study") != out.study.value("mode", "study"))
      throw Error(source + ": a " + part.study.value("mode", "study") + " report cannot join a " +
                  out.study.value("mode", "study") + " report");
    const std::string build = "the shards of one study come from one build of pbd";
    same_field(part, source, parts.front(), first, "pbd_version", build);
    same_field(part, source, parts.front(), first, "git_commit", build);
    for (const char* key : {"context/compiler", "context/flags", "context/build_type"})
      same_field(part, source, parts.front(), first, key, build);
    if (!rules.allow_mixed_machines)
      for (const char* key : {"context/cpu", "context/cores"})
        same_field(part, source, parts.front(), first, key,
                   "its timings do not compare with the other machine's; --allow-mixed-machines joins them and "
                   "lists each machine");
    json o = part.study.at("options");
    o.erase("shard");
    if (o != options)
      throw Error(source + ": its study options differ from " + first + "'s (" + o.dump() + " vs " +
                  options.dump() + ")");
  }
  check_shards(parts, sources);
  for (const Report& part : parts) {
    seconds += part.study.value("seconds", 0.0);
    for (const SceneInfo& s : part.scenes)
      if (!find_scene(out, s.name)) out.scenes.push_back(s);
    for (const Reference& r : part.references)
      if (std::none_of(out.references.begin(), out.references.end(),
                       [&](const Reference& o2) { return o2.scene == r.scene; }))
        out.references.push_back(r);
    for (const SharedNothing& s : part.shared_nothing) out.shared_nothing.push_back(s);
    for (const Record& r : part.records) out.records.push_back(r);
  }
  // Records in the order of the options' scenes, then as the shards ran them.
  const std::vector<std::string> scene_order = options.at("scenes").get<std::vector<std::string>>();
  auto rank = [&](const std::string& scene) {
    for (std::size_t i = 0; i < out.scenes.size(); ++i)
      if (out.scenes[i].name == scene) return i;
    return out.scenes.size();
  };
  // A scene's variants follow it in the order one run takes them (scene_variants.hpp), whichever shard ran them.
  const std::vector<std::string>& variants = variant_names();
  auto position = [&](const SceneInfo& s) {
    const std::string& base = s.base.empty() ? s.name : s.base;
    return std::make_pair(std::find(scene_order.begin(), scene_order.end(), base) - scene_order.begin(),
                          std::find(variants.begin(), variants.end(), s.variant) - variants.begin());
  };
  std::stable_sort(out.scenes.begin(), out.scenes.end(),
                   [&](const SceneInfo& a, const SceneInfo& b) { return position(a) < position(b); });
  std::stable_sort(out.records.begin(), out.records.end(), [&](const Record& a, const Record& b) {
    return std::make_tuple(rank(a.scene), a.budget(), a.substeps) < std::make_tuple(rank(b.scene), b.budget(), b.substeps);
  });
  std::stable_sort(out.references.begin(), out.references.end(),
                   [&](const Reference& a, const Reference& b) { return rank(a.scene) < rank(b.scene); });
  std::stable_sort(out.shared_nothing.begin(), out.shared_nothing.end(),
                   [&](const SharedNothing& a, const SharedNothing& b) { return rank(a.scene) < rank(b.scene); });
  // The context: the first part's, with the highest load any part saw; every part's own under "parts".
  json contexts = json::array();
  json& context = out.study["context"];
  for (const Report& part : parts) {
    const json& pc = part.study.at("context");
    contexts.push_back(pc);
    for (const char* key : {"load_before", "load_during", "load_during_max"})
      context[key] = std::max(context.value(key, 0.0), pc.value(key, 0.0));
  }
  out.study["parts"] = contexts;
  // Every machine is named; with more than one the context claims none of them.
  const json machines = machines_of(parts, sources);
  out.study["machines"] = machines;
  std::set<std::string> hosts;
  for (const json& m : machines)
    for (const json& h : m["hosts"]) hosts.insert(h.is_string() ? h.get<std::string>() : "?");
  std::string host_list;
  for (const std::string& h : hosts) host_list += (host_list.empty() ? "" : ", ") + h;
  if (hosts.size() > 1) context["host"] = host_list;
  if (machines.size() > 1) {
    std::string cpus = std::to_string(machines.size()) + " machines: ";
    for (std::size_t m = 0; m < machines.size(); ++m)
      cpus += (m ? "; " : "") + (machines[m]["cpu"].is_string() ? machines[m]["cpu"].get<std::string>() : "?") +
              " (" + machines[m]["cores"].dump() + " cores)";
    context["cpu"] = cpus;
    context["cores"] = nullptr;
    context["mixed_machines"] = true;
  }
  out.study["options"]["shard"] = nullptr;
  out.study["seconds"] = seconds;
  json merged = json::array();
  for (const std::string& s : sources) merged.push_back(s);
  out.study["merged_from"] = merged;
  finish(out);
  return out;
}

void print_table(std::ostream& out, const Report& report) {
  const json& c = report.study["context"];
  // A context field as text: "?" when it is missing or could not be found (null).
  auto text = [&](const char* key) {
    const auto it = c.find(key);
    return it == c.end() || it->is_null() ? std::string("?") : it->is_string() ? it->get<std::string>() : it->dump();
  };
  char line[1024];
  // Merged from several machines, the context's cpu names them all (merge_reports) and there is no one core count.
  const std::string machine = c.value("mixed_machines", false) ? text("cpu") : text("cpu") + ", " + text("cores") +
                                                                                   " cores";
  std::snprintf(line, sizeof line,
                "# pbd %s study (%s mode), %s, commit %s\n# %s; %s %s, %s\n# %s; other processes runnable: "
                "%.2f before, %.2f during (max %.0f); load average %s at the start\n",
                text("pbd_version").c_str(), report.study.value("mode", "study").c_str(), text("date").c_str(),
                text("commit").c_str(), text("compiler").c_str(), text("build_type").c_str(), text("flags").c_str(),
                report.records.empty() ? "no records" : report.records.front().precision.c_str(), machine.c_str(),
                c.value("load_before", 0.0), c.value("load_during", 0.0), c.value("load_during_max", 0.0),
                text("loadavg_start").c_str());
  out << line;
  int width = 14;  // the solver column: as wide as the longest name ("serial-colored+chebyshev")
  for (const Record& r : report.records) width = std::max(width, int(r.solver.size()));
  for (const SceneInfo& s : report.scenes) {
    std::snprintf(line, sizeof line, "\n## %s: %zu particles, %zu constraints, %d steps; primary error %s\n",
                  s.name.c_str(), s.particles, s.constraints, s.steps, s.primary_error.c_str());
    out << line;
    if (s.known_answer == "curve")
      out << "known answer: each fiber's force (from lambda) is its curve's at its strain (curve_pct); errors "
          << "averaged over steps " << s.average_from << ".." << s.steps << "\n";
    else if (!s.known_answer.empty())
      out << "known answer: " << (s.known_answer == "chain" ? "each link stretches by alpha*T_k (extension_pct)"
                                                            : "RMS stretch 0 at rest")
          << "; errors averaged over steps " << s.average_from << ".." << s.steps << " (settled: moved less than 1 mm RMS over them)\n";
    for (const Reference& r : report.references)
      if (r.scene == s.base) {
        std::string tried;
        for (const std::string& t : r.tried) tried += (tried.empty() ? " after " : ", ") + t;
        std::snprintf(line, sizeof line, "reference: %s, double, %dT, %dx%d%s, %.1f s; at half its budget one step "
                      "moves %s mm, the run ends %s mm away: %s\n", r.solver.c_str(), r.threads, r.substeps,
                      r.iterations, tried.c_str(), r.seconds, fmt(r.step_change_mm).c_str(),
                      fmt(r.trajectory_change_mm).c_str(),
                      r.converged        ? "converged"
                      : r.step_converged ? "*** NOT CONVERGED *** (one step is)"
                                         : "*** NOT CONVERGED ***");
        out << line;
        for (const std::string& f : r.failures) out << "  not converged: " << f << "\n";
      }
    const std::string primary_final = s.primary_error + "@end";
    std::snprintf(line, sizeof line, "%-*s %3s %8s %10s %21s %5s %7s %11s %11s %10s %10s %16s\n", width, "solver",
                  "thr", "split", "ms/step", "(min-max)", "cv%", "ns/proj", (s.primary_error + "~").c_str(),
                  primary_final.c_str(), "ref_mm", "traj_mm", "state_hash");
    out << line;
    for (const Record& r : report.records) {
      if (r.scene != s.name) continue;
      const std::string range = "(" + fmt(r.ms_per_step_min, "%.4g") + "-" + fmt(r.ms_per_step_max, "%.4g") + ")";
      std::snprintf(line, sizeof line, "%-*s %3d %8s %10.4g %21s %5.1f %7.1f %11s %11s %10s %10s %16s%s%s%s%s\n",
                    width, r.solver.c_str(), r.threads, r.split().c_str(), r.ms_per_step, range.c_str(),
                    100 * r.ms_per_step_cv, r.ns_per_projection(), fmt(r.primary_error).c_str(),
                    fmt(r.primary_error_final).c_str(), r.ref_error_mm ? fmt(*r.ref_error_mm).c_str() : "-",
                    r.trajectory_error_mm ? fmt(*r.trajectory_error_mm).c_str() : "-", hex(r.state_hash).c_str(),
                    r.pareto ? "  front" : "", r.busy ? "  BUSY" : "", r.repeatable ? "" : "  (runs differ!)",
                    r.settled && !*r.settled ? "  (moving)" : "");
      out << line;
    }
    bool header = false;
    const bool one_split = report.study.value("mode", "study") == "scaling";
    for (const BestSplit& b : report.best_splits) {
      if (b.scene != s.name || one_split) continue;
      if (!header) out << "best split per budget (lowest " << s.primary_error << "):";
      header = true;
      std::snprintf(line, sizeof line, "%s %s %dT %d: %dx%d", "", b.solver.c_str(), b.threads, b.budget, b.substeps,
                    b.iterations);
      out << line << ";";
    }
    if (header) out << "\n";
    for (const SharedNothing& sn : report.shared_nothing)
      if (sn.scene == s.name) {
        std::snprintf(line, sizeof line, "shared-nothing split on %d threads (this machine's ceiling): %.2fx\n",
                      sn.threads, median(sn.speedups));
        out << line;
      }
  }
  if (!report.time_to_target.empty()) {
    const TimeToTarget& first = report.time_to_target.front();
    std::snprintf(line, sizeof line, "\n# Time per step to reach %s%% (run-averaged primary error): the fastest point "
                  "at or below it\n", fmt(first.target).c_str());
    out << line;
  }
  for (const TimeToTarget& t : report.time_to_target) {
    if (t.reached)
      std::snprintf(line, sizeof line, "%-24s %-*s %dT: %10.4g ms/step at %dx%d (%s %s)\n", t.scene.c_str(), width,
                    t.solver.c_str(), t.threads, t.ms_per_step, t.substeps, t.iterations, t.measure.c_str(),
                    fmt(t.primary_error).c_str());
    else
      std::snprintf(line, sizeof line, "%-24s %-*s %dT: not reached; lowest %s %s at %dx%d (%.4g ms/step)\n",
                    t.scene.c_str(), width, t.solver.c_str(), t.threads, t.measure.c_str(),
                    fmt(t.primary_error).c_str(), t.substeps, t.iterations, t.ms_per_step);
    out << line;
  }
  if (!report.dominance.empty())
    out << "\n# Dominance: for each serial point, a point of the parallel solver at its most threads with lower "
           "ms/step and no higher primary error\n";
  for (const Dominance& d : report.dominance) {
    std::string missing;
    for (const std::string& u : d.undominated) missing += (missing.empty() ? "" : ",") + u;
    std::snprintf(line, sizeof line, "%-14s %-8s %dT on %-14s: %d of %d serial points dominated%s%s\n",
                  d.scene.c_str(), d.solver.c_str(), d.threads, d.measure.c_str(),
                  d.serial_points - int(d.undominated.size()), d.serial_points,
                  missing.empty() ? "" : "; not ", missing.c_str());
    out << line;
  }
  if (!report.strong.empty()) out << "\n# Strong scaling: speed-up over the same solver on 1 thread\n";
  for (const StrongScaling& s : report.strong) {
    if (s.threads == 1) continue;
    std::snprintf(line, sizeof line, "%-10s %-8s %dT: %.2fx (%.2f-%.2f)\n", s.scene.c_str(), s.solver.c_str(),
                  s.threads, s.speedup, s.speedup_min, s.speedup_max);
    out << line;
  }
  for (const json& w : report.study["warnings"]) out << "\n*** WARNING: " << w.get<std::string>() << "\n";
}

void print_csv(std::ostream& out, const Report& report) {
  std::set<std::string> measures;
  for (const Record& r : report.records)
    for (const auto& [name, v] : r.errors) measures.insert(name);
  out << "scene,solver,threads,budget,substeps,iterations,steps,precision,repeats,ms_per_step,ms_per_step_min,"
         "ms_per_step_max,ms_per_step_cv,ns_per_projection,particles,constraints,colors,primary_error,ref_error_mm,"
         "ref_error_max_mm,trajectory_error_mm,energy_drift,state_hash,repeatable,load,busy,pareto,variant,timing_steps,"
         "primary_error_final,settle_motion_mm,settled";
  for (const std::string& m : measures) out << "," << m << "_rms," << m << "_max";
  for (const std::string& m : measures) out << "," << m << "_rms_final," << m << "_max_final";
  out << "\n";
  auto opt = [](const std::optional<double>& v) { return v ? fmt(*v, "%.6g") : std::string(); };
  for (const Record& r : report.records) {
    out << r.scene << "," << r.solver << "," << r.threads << "," << r.budget() << "," << r.substeps << ","
        << r.iterations << "," << r.steps << "," << r.precision << "," << r.repeats << ","
        << fmt(r.ms_per_step, "%.6g") << "," << fmt(r.ms_per_step_min, "%.6g") << ","
        << fmt(r.ms_per_step_max, "%.6g") << "," << fmt(r.ms_per_step_cv, "%.4f") << ","
        << fmt(r.ns_per_projection(), "%.4g") << "," << r.particles << "," << r.constraints << "," << r.colors
        << "," << fmt(r.primary_error, "%.6g") << "," << opt(r.ref_error_mm) << "," << opt(r.ref_error_max_mm) << ","
        << opt(r.trajectory_error_mm) << "," << opt(r.energy_drift) << "," << hex(r.state_hash) << ","
        << (r.repeatable ? 1 : 0) << "," << fmt(r.load, "%.2f") << "," << (r.busy ? 1 : 0) << ","
        << (r.pareto ? 1 : 0) << "," << r.variant << "," << r.timing_steps << ","
        << fmt(r.primary_error_final, "%.6g") << "," << opt(r.settle_motion_mm) << ","
        << (r.settled ? (*r.settled ? "1" : "0") : "");
    for (const Errors* e : {&r.errors, &r.errors_final})
      for (const std::string& m : measures) {
        const auto it = e->find(m);
        if (it == e->end()) out << ",,";
        else out << "," << fmt(it->second.rms, "%.6g") << "," << fmt(it->second.max, "%.6g");
      }
    out << "\n";
  }
}

}  // namespace pbd::cli
