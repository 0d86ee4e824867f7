#include "study_options.hpp"

#include "pbd/error.hpp"
#include "scene_dir.hpp"
#include "study_scenes.hpp"

#include <algorithm>
#include <charconv>

namespace pbd::cli {
namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    if (end > begin) out.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return out;
}

// Comma-separated integers in [lo, hi], sorted, duplicates dropped.
std::vector<int> int_list(const std::string& flag, const std::string& text, int lo, int hi) {
  std::vector<int> out;
  for (const std::string& item : split(text)) {
    int v = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec != std::errc() || end != item.data() + item.size())
      throw Error(flag + ": \"" + item + "\" is not an integer (expected a comma-separated list such as 1,2,4)");
    if (v < lo || v > hi)
      throw Error(flag + ": " + item + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    out.push_back(v);
  }
  if (out.empty()) throw Error(flag + ": the list is empty");
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<StudySolver> solver_list(const std::string& text) {
  std::vector<StudySolver> out;
  for (const std::string& item : split(text)) {
    const auto s = parse_solver(item);
    if (!s) throw Error("--solvers: unknown solver \"" + item + "\" (valid: " + solver_names() + ")");
    if (std::any_of(out.begin(), out.end(), [&](const StudySolver& o) { return o.solver == *s; })) continue;
    out.push_back({item, *s, is_parallel(*s)});
  }
  if (out.empty()) throw Error("--solvers: the list is empty (valid: " + solver_names() + ")");
  return out;
}

}  // namespace

std::vector<std::string> default_study_scenes() { return builtin_scene_names(); }

StudyPlan make_plan(const StudyOptions& o) {
  StudyPlan plan;
  plan.quick = o.quick;
  // --quick: the smoke test (every built-in scene, every solver, 1 and 2 threads, 1 and 4 iterations, 20 steps,
  // one timed run, a 50-iteration reference); options given explicitly still win.
  for (const std::string& s : o.scenes)
    for (const std::string& name : split(s)) plan.scenes.push_back(name);
  if (plan.scenes.empty()) plan.scenes = default_study_scenes();
  for (const std::string& name : plan.scenes) check_study_scene(name);
  plan.solvers = solver_list(o.solvers);
  plan.threads = int_list("--threads", o.threads, 1, 1024);
  plan.iterations = int_list("--iterations", o.quick && !o.given_iterations ? "1,4" : o.iterations, 1, 100000);
  plan.substeps = int_list("--substeps", o.substeps, 1, 10000);
  plan.steps = o.steps > 0 ? o.steps : (o.quick ? 20 : 0);
  if (o.precision != "float" && o.precision != "double")
    throw Error("--precision: \"" + o.precision + "\" is not float or double");
  plan.double_precision = o.precision == "double";
  plan.repeats = o.repeats > 0 ? o.repeats : (o.quick ? 1 : 5);
  plan.reference_iterations = o.reference_iterations > 0 ? o.reference_iterations : (o.quick ? 50 : 200);
  if (plan.reference_iterations < 2) throw Error("--reference-iterations: must be at least 2");
  plan.json = o.json;
  plan.plots = o.plots;
  return plan;
}

}  // namespace pbd::cli
