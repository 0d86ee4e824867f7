#include "study_report.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <ostream>

namespace pbd::cli {

double Record::ns_per_projection() const {
  const double projections = double(constraints) * substeps * iterations;
  return projections > 0.0 ? ms_per_step * 1e6 / projections : 0.0;
}

namespace {

std::string hex(std::uint64_t h) {
  char s[19];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

double error_of(const Record& r, const std::string& error) {
  return error == "ref_error" ? r.ref_error : r.rms_violation;
}

nlohmann::json optional_number(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json to_json(const Record& r) {
  nlohmann::json violations = nlohmann::json::object();
  for (const auto& t : r.violations)
    violations[t.type] = {{"rms", t.value.rms}, {"max", t.value.max}, {"count", t.value.count}};
  return {{"scene", r.scene},
          {"solver", r.solver},
          {"threads", r.threads},
          {"iterations", r.iterations},
          {"substeps", r.substeps},
          {"steps", r.steps},
          {"precision", r.precision},
          {"repeats", r.repeats},
          {"ms_per_step", r.ms_per_step},
          {"ms_per_step_min", r.ms_per_step_min},
          {"ns_per_projection", r.ns_per_projection()},
          {"particles", r.particles},
          {"constraints", r.constraints},
          {"colors", r.colors},
          {"rms_violation", r.rms_violation},
          {"max_violation", r.max_violation},
          {"violations", violations},
          {"ref_error", r.ref_error},
          {"ref_error_max", r.ref_error_max},
          {"trajectory_error", r.trajectory_error},
          {"energy_drift", optional_number(r.energy_drift)},
          {"state_hash", hex(r.state_hash)},
          {"repeatable", r.repeatable}};
}

nlohmann::json to_json(const Reference& r) {
  return {{"scene", r.scene},
          {"substeps", r.substeps},
          {"steps", r.steps},
          {"solver", "serial"},
          {"precision", "double"},
          {"iterations", r.iterations},
          {"size", r.size},
          {"step_convergence", r.step_convergence},
          {"step_convergence_max", r.step_convergence_max},
          {"trajectory_convergence", r.trajectory_convergence},
          {"rms_violation", r.rms_violation},
          {"max_violation", r.max_violation},
          {"energy_drift", optional_number(r.energy_drift)},
          {"seconds", r.seconds}};
}

std::string list(const std::vector<int>& v) {
  std::string s;
  for (int x : v) {
    if (!s.empty()) s += ',';
    s += std::to_string(x);
  }
  return s;
}

}  // namespace

std::vector<Dominance> dominance(const std::vector<Record>& records) {
  std::vector<Dominance> out;
  for (const std::string solver : {"colored", "block"}) {
    std::map<std::pair<std::string, int>, int> max_threads;  // (scene, substeps) → most threads of its records
    std::vector<std::pair<std::string, int>> order;
    for (const Record& r : records) {
      const auto key = std::make_pair(r.scene, r.substeps);
      if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
      if (r.solver == solver) max_threads[key] = std::max(max_threads[key], r.threads);
    }
    for (const auto& key : order) {
      if (!max_threads.count(key)) continue;
      for (const std::string error : {"ref_error", "rms_violation"}) {
        Dominance d{key.first, key.second, solver, max_threads[key], error, 0, {}};
        for (const Record& s : records) {
          if (s.scene != key.first || s.substeps != key.second || s.solver != "serial") continue;
          ++d.serial_points;
          const bool dominated = std::any_of(records.begin(), records.end(), [&](const Record& c) {
            return c.scene == s.scene && c.substeps == s.substeps && c.solver == solver && c.threads == d.threads &&
                   c.ms_per_step < s.ms_per_step && error_of(c, error) <= error_of(s, error);
          });
          if (!dominated) d.undominated.push_back(s.iterations);
        }
        if (d.serial_points) out.push_back(d);
      }
    }
  }
  return out;
}

void print_table(std::ostream& out, const std::vector<Record>& records, const std::vector<Dominance>& dom) {
  char line[512];
  std::string scene;
  for (const Record& r : records) {
    if (r.scene != scene) {
      scene = r.scene;
      std::snprintf(line, sizeof line, "\n# %s: %zu particles, %zu constraints, %d steps, %s\n", r.scene.c_str(),
                    r.particles, r.constraints, r.steps, r.precision.c_str());
      out << line;
      std::snprintf(line, sizeof line, "%-15s %3s %5s %4s %10s %10s %7s %6s %10s %10s %10s %10s %16s\n", "solver",
                    "thr", "iter", "sub", "ms/step", "ms_min", "ns/proj", "colors", "rms_viol", "max_viol",
                    "ref_error", "drift", "state_hash");
      out << line;
    }
    const std::string drift = r.energy_drift ? [&] {
      char s[32];
      std::snprintf(s, sizeof s, "%+.3e", *r.energy_drift);
      return std::string(s);
    }() : std::string("-");
    std::snprintf(line, sizeof line,
                  "%-15s %3d %5d %4d %10.4f %10.4f %7.1f %6zu %10.3e %10.3e %10.3e %10s %16s%s\n", r.solver.c_str(),
                  r.threads, r.iterations, r.substeps, r.ms_per_step, r.ms_per_step_min, r.ns_per_projection(),
                  r.colors, r.rms_violation, r.max_violation, r.ref_error, drift.c_str(), hex(r.state_hash).c_str(),
                  r.repeatable ? "" : "  (runs differ!)");
    out << line;
  }
  if (dom.empty()) return;
  out << "\n# Do colored and block (most threads) dominate serial? For each serial point: a point of theirs with lower "
         "ms/step and no higher error.\n";
  for (const Dominance& d : dom) {
    std::snprintf(line, sizeof line, "%-14s substeps %d, %-7s on %d threads, %-13s: %d of %d serial points dominated%s%s\n",
                  d.scene.c_str(), d.substeps, d.solver.c_str(), d.threads, d.error.c_str(),
                  d.serial_points - int(d.undominated.size()), d.serial_points,
                  d.undominated.empty() ? "" : "; not at iterations ", list(d.undominated).c_str());
    out << line;
  }
}

nlohmann::json report_json(const StudyPlan& plan, const nlohmann::json& environment,
                           const std::vector<Reference>& references, const std::vector<Record>& records,
                           const std::vector<Dominance>& dom) {
  nlohmann::json solvers = nlohmann::json::array();
  for (const auto& s : plan.solvers) solvers.push_back(s.name);
  nlohmann::json study = environment;
  study["options"] = {{"scenes", plan.scenes},
                      {"solvers", solvers},
                      {"threads", plan.threads},
                      {"iterations", plan.iterations},
                      {"substeps", plan.substeps},
                      {"steps", plan.steps > 0 ? nlohmann::json(plan.steps) : nlohmann::json("scene")},
                      {"precision", plan.double_precision ? "double" : "float"},
                      {"repeats", plan.repeats},
                      {"reference_iterations", plan.reference_iterations},
                      {"quick", plan.quick}};
  nlohmann::json doc = {{"study", study},
                        {"references", nlohmann::json::array()},
                        {"records", nlohmann::json::array()},
                        {"dominance", nlohmann::json::array()}};
  for (const auto& r : references) doc["references"].push_back(to_json(r));
  for (const auto& r : records) doc["records"].push_back(to_json(r));
  for (const auto& d : dom)
    doc["dominance"].push_back({{"scene", d.scene},
                                {"substeps", d.substeps},
                                {"solver", d.solver},
                                {"threads", d.threads},
                                {"error", d.error},
                                {"serial_points", d.serial_points},
                                {"undominated_iterations", d.undominated}});
  return doc;
}

}  // namespace pbd::cli
