// What a report derives from its records (study_report.hpp's finish and check_reference): the Pareto flags, the best
// split per budget, dominance, strong scaling, the time to the target, the references' check and the warnings. Every
// pass goes scene by scene through an index (report_index.hpp) or sorts, so that a merged report of tens of
// thousands of records is finished in n log n.
#include "study_report.hpp"

#include "load_monitor.hpp"
#include "report_index.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Whether a measure is in % (the headline's target applies to it): stretch_pct, area_pct, volume_pct, ...
bool percent_measure(const std::string& m) { return m.size() > 4 && m.compare(m.size() - 4, 4, "_pct") == 0; }

// The first scene of each name.
std::map<std::string, const SceneInfo*> scenes_by_name(const Report& report) {
  std::map<std::string, const SceneInfo*> out;
  for (const SceneInfo& s : report.scenes) out.emplace(s.name, &s);
  return out;
}
const SceneInfo* find(const std::map<std::string, const SceneInfo*>& scenes, const std::string& name) {
  const auto it = scenes.find(name);
  return it == scenes.end() ? nullptr : it->second;
}

// The Pareto flags of one scene's records: a record is off the front when another is at most as slow and at most
// as wrong, and better in one of the two. Sorted by time (then error), that is: a faster record at most as wrong,
// or an equally fast one less wrong. A NaN (nothing measured) compares false: it neither dominates nor is dominated.
void mark_pareto(std::vector<Record>& records, const std::vector<std::size_t>& scene) {
  std::vector<std::size_t> order;
  for (std::size_t i : scene) {
    Record& r = records[i];
    if (std::isnan(r.ms_per_step) || std::isnan(r.primary_error)) r.pareto = true;
    else order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(records[a].ms_per_step, records[a].primary_error) <
           std::make_pair(records[b].ms_per_step, records[b].primary_error);
  });
  bool any_faster = false;
  double faster_error = INFINITY;  // the lowest error of the records faster than the current time
  for (std::size_t g = 0; g < order.size();) {
    const double ms = records[order[g]].ms_per_step, least = records[order[g]].primary_error;
    std::size_t h = g;
    while (h < order.size() && records[order[h]].ms_per_step == ms) ++h;
    for (std::size_t k = g; k < h; ++k) {
      Record& r = records[order[k]];
      r.pareto = !((any_faster && faster_error <= r.primary_error) || least < r.primary_error);
    }
    for (std::size_t k = g; k < h; ++k) faster_error = std::min(faster_error, records[order[k]].primary_error);
    any_faster = true;
    g = h;
  }
}

// Best split per (scene, solver, threads, budget): the lowest primary error, the faster on a tie.
std::vector<BestSplit> best_splits(const std::vector<Record>& records) {
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
  std::vector<BestSplit> out;
  for (const auto& key : order) {
    const Record& r = records[best[key]];
    out.push_back({r.scene, r.solver, r.threads, r.budget(), r.substeps, r.iterations, r.ms_per_step,
                   r.primary_error});
  }
  return out;
}

// Does `solver` at `threads` dominate each serial point of one scene? A serial point is dominated by a point that is
// faster with no higher error: with the candidates sorted by time, the lowest error among those faster than it.
Dominance dominance(const SceneInfo& scene, const std::string& solver, int threads, const std::vector<Record>& records,
                    const std::vector<std::size_t>& of_scene) {
  std::vector<std::pair<double, double>> candidates;  // (ms per step, primary error)
  for (std::size_t i : of_scene) {
    const Record& c = records[i];
    if (c.solver == solver && c.threads == threads && !std::isnan(c.ms_per_step) && !std::isnan(c.primary_error))
      candidates.emplace_back(c.ms_per_step, c.primary_error);
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<double> times, lowest;  // lowest[k]: the lowest error of candidates 0..k
  for (const auto& [ms, error] : candidates) {
    times.push_back(ms);
    lowest.push_back(lowest.empty() ? error : std::min(lowest.back(), error));
  }
  Dominance d{scene.name, solver, scene.primary_error, threads, 0, {}};
  for (std::size_t i : of_scene) {
    const Record& s = records[i];
    if (s.solver != "serial") continue;
    ++d.serial_points;
    const std::size_t faster = std::size_t(std::lower_bound(times.begin(), times.end(), s.ms_per_step) - times.begin());
    if (!(faster > 0 && lowest[faster - 1] <= s.primary_error)) d.undominated.push_back(s.split());
  }
  return d;
}

// Dominance of serial by each parallel solver at its most threads, per scene.
std::vector<Dominance> dominance(const Report& report, const NameIndex& by_scene) {
  std::vector<Dominance> out;
  for (const SceneInfo& scene : report.scenes) {
    const std::vector<std::size_t>& of_scene = indices_of(by_scene, scene.name);
    std::map<std::string, int> most;
    std::vector<std::string> solvers;
    for (std::size_t i : of_scene) {
      const Record& r = report.records[i];
      if (r.solver == "serial") continue;
      if (!most.count(r.solver)) solvers.push_back(r.solver);
      most[r.solver] = std::max(most[r.solver], r.threads);
    }
    for (const std::string& solver : solvers) {
      Dominance d = dominance(scene, solver, most[solver], report.records, of_scene);
      if (d.serial_points) out.push_back(std::move(d));
    }
  }
  return out;
}

// Strong scaling: speed-up over the same solver on 1 thread at the same split, round by round.
std::vector<StrongScaling> strong_scaling(const std::vector<Record>& records) {
  std::map<std::tuple<std::string, std::string, int, int>, const Record*> one_thread;  // the first of each
  for (const Record& o : records)
    if (o.threads == 1) one_thread.emplace(std::make_tuple(o.scene, o.solver, o.substeps, o.iterations), &o);
  std::vector<StrongScaling> out;
  for (const Record& r : records) {
    const auto it = one_thread.find(std::make_tuple(r.scene, r.solver, r.substeps, r.iterations));
    if (it == one_thread.end()) continue;
    const Record& one = *it->second;
    std::vector<double> ratios;
    for (std::size_t k = 0; k < std::min(one.ms.size(), r.ms.size()); ++k) ratios.push_back(one.ms[k] / r.ms[k]);
    if (ratios.empty()) continue;
    const auto [lo, hi] = std::minmax_element(ratios.begin(), ratios.end());
    out.push_back({r.scene, r.solver, r.particles, r.threads, r.ms_per_step, r.ms_per_step_min, r.ms_per_step_max,
                   median(ratios), *lo, *hi});
  }
  return out;
}

std::vector<TimeToTarget> times_to_target(const Report& report, const std::map<std::string, const SceneInfo*>& scenes) {
  std::vector<TimeToTarget> out;
  std::map<std::tuple<std::string, std::string, int>, std::size_t> index;  // (scene, solver, threads) → out
  const double target = report.study.value("options", json::object()).value("target_pct", 1.0);
  for (const Record& r : report.records) {
    const SceneInfo* scene = find(scenes, r.scene);
    if (!scene || !percent_measure(scene->primary_error)) continue;
    const bool reached = r.primary_error <= target;
    const auto [it, added] = index.emplace(std::make_tuple(r.scene, r.solver, r.threads), out.size());
    if (added) {
      out.push_back({r.scene, r.base(), r.variant, r.solver, r.threads, scene->primary_error, target, reached,
                     r.substeps, r.iterations, r.ms_per_step, r.primary_error});
      continue;
    }
    TimeToTarget& t = out[it->second];
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

// The reference check over the records of its scene (all variants).
void check_reference_on(Reference& ref, const std::vector<const Record*>& records, bool by_reference) {
  ref.failures.clear();
  double step = INFINITY, trajectory = INFINITY;
  std::map<std::string, double> smallest;
  for (const Record* r : records) {
    if (r->ref_error_mm) step = std::min(step, *r->ref_error_mm);
    if (r->trajectory_error_mm) trajectory = std::min(trajectory, *r->trajectory_error_mm);
    for (const auto& [m, v] : r->errors) {
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

std::vector<const Record*> records_of(const std::vector<Record>& records, const std::vector<std::size_t>& indices) {
  std::vector<const Record*> out;
  out.reserve(indices.size());
  for (std::size_t i : indices) out.push_back(&records[i]);
  return out;
}

json warnings(const Report& report, const NameIndex& by_scene) {
  const std::vector<Record>& records = report.records;
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
    for (std::size_t i : indices_of(by_scene, scene.name)) {
      const Record& r = records[i];
      if (!r.settled) continue;
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
  return warnings;
}

}  // namespace

void check_reference(Reference& ref, const std::vector<Record>& records, bool by_reference) {
  std::vector<const Record*> of_scene;
  for (const Record& r : records)
    if (r.base() == ref.scene) of_scene.push_back(&r);
  check_reference_on(ref, of_scene, by_reference);
}

void finish(Report& report) {
  std::vector<Record>& records = report.records;
  const auto scenes = scenes_by_name(report);
  // A scene judged against its reference takes its primary error from it (NaN where none was measured).
  for (Record& r : records) {
    const SceneInfo* scene = find(scenes, r.scene);
    if (!scene || scene->primary_error != kReferenceMeasure) continue;
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    r.primary_error = r.ref_error_mm.value_or(kNone);
    r.primary_error_final = r.trajectory_error_mm.value_or(kNone);
  }
  const NameIndex by_scene = index_by(records, [](const Record& r) { return r.scene; });
  for (const auto& [name, of_scene] : by_scene) mark_pareto(records, of_scene);
  report.best_splits = best_splits(records);
  report.dominance = dominance(report, by_scene);
  const bool scaling = report.study.value("mode", "study") == "scaling";
  report.strong.clear();
  if (scaling) report.strong = strong_scaling(records);
  const NameIndex by_base = index_by(records, [](const Record& r) { return r.base(); });
  for (Reference& ref : report.references) {
    const SceneInfo* scene = find(scenes, ref.scene);
    check_reference_on(ref, records_of(records, indices_of(by_base, ref.scene)),
                       scene && scene->primary_error == kReferenceMeasure);
  }
  report.time_to_target.clear();
  if (!scaling) report.time_to_target = times_to_target(report, scenes);
  json w = warnings(report, by_scene);
  report.study["busy"] = !w.empty();
  report.study["warnings"] = std::move(w);
}

}  // namespace pbd::cli
