#include "study_report.hpp"

#include "pbd/error.hpp"
#include "report_index.hpp"
#include "scene_variants.hpp"

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

// JSON numbers cannot be infinite: a diverged error is written as null (and read back as infinity).
json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json errors_json(const Errors& e) {
  json out = json::object();
  for (const auto& [name, v] : e) out[name] = {{"rms", finite(v.rms)}, {"max", finite(v.max)}};
  return out;
}

}  // namespace

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
    // A run has one speed-up per round; with none (a report read back refuses that) there is nothing to summarize.
    json summary = {{"speedup", nullptr}, {"speedup_min", nullptr}, {"speedup_max", nullptr}};
    if (!s.speedups.empty()) {
      const auto [lo, hi] = std::minmax_element(s.speedups.begin(), s.speedups.end());
      summary = {{"speedup", median(s.speedups)}, {"speedup_min", *lo}, {"speedup_max", *hi}};
    }
    json entry = {{"scene", s.scene}, {"threads", s.threads}, {"speedups", s.speedups}};
    entry.update(summary);
    sn.push_back(std::move(entry));
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

void print_table(std::ostream& out, const Report& report) {
  static const json no_context = json::object();
  const json& c = report.study.contains("context") ? report.study["context"] : no_context;
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
  // Each scene's items, looked up rather than searched for: a merged report has thousands of scenes' records.
  const NameIndex records = index_by(report.records, [](const Record& r) { return r.scene; });
  const NameIndex references = index_by(report.references, [](const Reference& r) { return r.scene; });
  const NameIndex best_splits = index_by(report.best_splits, [](const BestSplit& b) { return b.scene; });
  const NameIndex shared_nothing = index_by(report.shared_nothing, [](const SharedNothing& s) { return s.scene; });
  const bool one_split = report.study.value("mode", "study") == "scaling";
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
    for (std::size_t i : indices_of(references, s.base)) {
      const Reference& r = report.references[i];
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
    for (std::size_t i : indices_of(records, s.name)) {
      const Record& r = report.records[i];
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
    for (std::size_t i : one_split ? std::vector<std::size_t>() : indices_of(best_splits, s.name)) {
      const BestSplit& b = report.best_splits[i];
      if (!header) out << "best split per budget (lowest " << s.primary_error << "):";
      header = true;
      std::snprintf(line, sizeof line, "%s %s %dT %d: %dx%d", "", b.solver.c_str(), b.threads, b.budget, b.substeps,
                    b.iterations);
      out << line << ";";
    }
    if (header) out << "\n";
    for (std::size_t i : indices_of(shared_nothing, s.name)) {
      const SharedNothing& sn = report.shared_nothing[i];
      std::snprintf(line, sizeof line, "shared-nothing split on %d threads (this machine's ceiling): %s\n",
                    sn.threads, sn.speedups.empty() ? "no rounds" : (fmt(median(sn.speedups), "%.2f") + "x").c_str());
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
  if (report.study.contains("warnings"))
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
