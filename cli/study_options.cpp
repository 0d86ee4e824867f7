#include "study_options.hpp"

#include "pbd/error.hpp"
#include "scene_dir.hpp"
#include "scene_variants.hpp"
#include "study_scenes.hpp"

#include <algorithm>
#include <charconv>
#include <optional>
#include <cstdlib>
#include <oneapi/tbb/global_control.h>

namespace pbd::cli {
namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    if (end > begin) out.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return out;
}

bool parse_int(const std::string& text, int& v) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  return ec == std::errc() && end == text.data() + text.size();
}

// Comma-separated integers in [lo, hi], sorted, duplicates dropped.
std::vector<int> int_list(const std::string& flag, const std::string& text, int lo, int hi) {
  std::vector<int> out;
  for (const std::string& item : split_list(text)) {
    int v = 0;
    if (!parse_int(item, v))
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
  const std::string suffix = "+chebyshev";
  for (const std::string& item : split_list(text)) {
    const bool chebyshev = item.size() > suffix.size() && item.compare(item.size() - suffix.size(), suffix.size(),
                                                                       suffix) == 0;
    const std::string base = chebyshev ? item.substr(0, item.size() - suffix.size()) : item;
    const auto s = parse_solver(base);
    if (!s)
      throw Error("--solvers: unknown solver \"" + item + "\" (valid: " + solver_names() +
                  ", and any but serial with +chebyshev)");
    if (chebyshev && *s == Solver::serial)
      throw Error("--solvers: \"" + item + "\": the serial reference is never accelerated (serial-colored can be)");
    if (std::any_of(out.begin(), out.end(), [&](const StudySolver& o) { return o.name == item; })) continue;
    out.push_back({item, *s, is_parallel(*s), chebyshev});
  }
  if (out.empty()) throw Error("--solvers: the list is empty (valid: " + solver_names() + ")");
  return out;
}

std::string all_threads() {
  const int n = machine_threads();
  std::string s;
  for (int t = 1; t <= n; ++t) {
    if (t > 1) s += ',';
    s += std::to_string(t);
  }
  return n == 1 ? "1" : s;
}

// An environment variable as an integer: nothing when it is not set; throws pbd::Error when it is not an integer.
std::optional<int> int_env(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return std::nullopt;
  int n = 0;
  if (!parse_int(v, n)) throw Error(std::string("--shard auto: ") + name + "=" + v + " is not an integer");
  return n;
}

// --shard auto: part I of N from a Slurm job array. The array must be contiguous (sbatch --array=MIN-MAX): task
// SLURM_ARRAY_TASK_ID is part ID − MIN + 1 of MAX − MIN + 1 (SLURM_ARRAY_TASK_COUNT when MAX is not set, MIN 1 when
// it is not set either).
void slurm_shard(int& shard, int& shards) {
  const auto id = int_env("SLURM_ARRAY_TASK_ID");
  if (!id)
    throw Error("--shard auto: not in a Slurm job array (SLURM_ARRAY_TASK_ID is not set; submit with sbatch "
                "--array=1-N, or give --shard I/N)");
  const auto count = int_env("SLURM_ARRAY_TASK_COUNT"), min = int_env("SLURM_ARRAY_TASK_MIN"),
             max = int_env("SLURM_ARRAY_TASK_MAX"), step = int_env("SLURM_ARRAY_TASK_STEP");
  if (!count && !max)
    throw Error("--shard auto: SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_COUNT nor "
                "SLURM_ARRAY_TASK_MAX is: the number of parts is unknown");
  const int first = min.value_or(1);
  const int n = max ? *max - first + 1 : *count;
  if ((step && *step != 1) || (count && *count != n))
    throw Error("--shard auto: the job array is not contiguous (SLURM_ARRAY_TASK_COUNT " +
                (count ? std::to_string(*count) : std::string("unset")) + ", MIN " + std::to_string(first) +
                ", MAX " + (max ? std::to_string(*max) : std::string("unset")) +
                "); submit it as --array=MIN-MAX, every index once");
  if (n < 1 || *id < first || *id > first + n - 1)
    throw Error("--shard auto: SLURM_ARRAY_TASK_ID " + std::to_string(*id) + " is outside the array " +
                std::to_string(first) + ".." + std::to_string(first + n - 1));
  shard = *id - first + 1;
  shards = n;
}

// Refuses thread counts above what this machine runs: a task arena of more threads runs on fewer, and its points
// would be reported as timed on threads that never ran. --estimate runs nothing and may plan for another machine
// (scripts/slurm-study checks the options of the nodes' parts on the machine that submits them).
void check_machine_threads(const StudyPlan& plan) {
  const int most = machine_threads();
  if (plan.estimate || plan.threads.back() <= most) return;
  throw Error("--threads: " + std::to_string(plan.threads.back()) + " is more than the " + std::to_string(most) +
              " threads this machine runs (its points would be timed on " + std::to_string(most) +
              "); give at most " + std::to_string(most));
}

}  // namespace

int machine_threads() {
  return std::max(1, int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
}

std::vector<std::string> default_study_scenes() {
  // Every built-in scene but `pile`, the granular scale case (10,000 grains: one of its runs takes seconds, and the
  // study makes hundreds). `--scene pile` studies it.
  std::vector<std::string> out;
  for (const std::string& name : builtin_scene_names())
    if (name != "pile") out.push_back(name);
  for (const char* scene : {"cloth30", "cloth100", "cloth300", "cloth30-rest", "chain30"}) out.push_back(scene);
  return out;
}

std::vector<std::string> default_scaling_scenes() { return {"cloth30", "cloth100", "cloth300", "cloth1000"}; }

std::vector<Split> splits_of(int budget) {
  std::vector<Split> out;
  for (int s = 1; s <= budget; ++s)
    if (budget % s == 0) out.push_back({s, budget / s});
  return out;
}

std::vector<Split> study_splits(int budget) {
  if (budget <= kAllSplitsBudget) return splits_of(budget);
  return {{budget, 1}};
}

Split parse_split(const std::string& flag, const std::string& text) {
  const std::size_t x = text.find('x');
  Split s;
  if (x == std::string::npos || !parse_int(text.substr(0, x), s.substeps) ||
      !parse_int(text.substr(x + 1), s.iterations))
    throw Error(flag + ": \"" + text + "\" is not SUBSTEPSxITERATIONS (such as 2x5)");
  if (s.substeps < 1 || s.substeps > kMaxSubsteps || s.iterations < 1 || s.iterations > kMaxIterations)
    throw Error(flag + ": \"" + text + "\" is out of range (substeps 1.." + std::to_string(kMaxSubsteps) +
                ", iterations 1.." + std::to_string(kMaxIterations) + ")");
  return s;
}

StudyPlan make_plan(const StudyOptions& o) {
  StudyPlan plan;
  plan.quick = o.quick;
  plan.estimate = o.estimate;
  plan.scaling = o.scaling;
  for (const std::string& s : o.scenes)
    for (const std::string& name : split_list(s))
      if (std::find(plan.scenes.begin(), plan.scenes.end(), name) == plan.scenes.end()) plan.scenes.push_back(name);
  if (plan.scenes.empty()) plan.scenes = o.scaling ? default_scaling_scenes() : default_study_scenes();
  if (o.scenes.empty() && o.quick && !o.scaling)  // --quick leaves out the 300² cloth
    plan.scenes.erase(std::remove(plan.scenes.begin(), plan.scenes.end(), "cloth300"), plan.scenes.end());
  for (const std::string& name : plan.scenes) check_study_scene(name);
  // Main mode: every solver (serial is the baseline); scaling mode: the parallel ones.
  plan.solvers = solver_list(!o.solvers.empty() ? o.solvers : o.scaling ? "colored,jacobi,block"
                                                                          : "serial,colored,jacobi,block");
  plan.default_solvers = o.solvers.empty();
  // The default of the main study, 1 and 2, is 1 alone on a machine that runs one thread.
  const std::string default_threads = o.scaling || machine_threads() == 1 ? all_threads() : "1,2";
  plan.threads = int_list("--threads", !o.threads.empty() ? o.threads : default_threads, 1, kMaxStudyThreads);
  check_machine_threads(plan);
  // --quick: the smoke test: budgets of 2 and 4 sweeps, at most 20 steps, one timed run, an 8x1 reference.
  plan.default_budgets = o.budgets.empty();
  plan.budgets = int_list("--budgets", !o.budgets.empty() ? o.budgets : o.quick ? "2,4" : "1,2,4,8,16,32,64,128,256",
                          1, kMaxStudyBudget);
  if (!o.split.empty()) plan.split = parse_split("--split", o.split);
  plan.steps = o.steps;
  plan.max_steps = o.quick ? 20 : 0;
  if (o.precision != "float" && o.precision != "double")
    throw Error("--precision: \"" + o.precision + "\" is not float or double");
  plan.double_precision = o.precision == "double";
  plan.repeats = o.repeats > 0 ? o.repeats : (o.quick ? 1 : 3);
  // The reference starts at twice the largest budget, as substeps (substeps converge the time discretisation too).
  const std::string first_reference = std::to_string(2 * plan.budgets.back()) + "x1";
  plan.reference = parse_split("--reference", !o.reference.empty() ? o.reference : first_reference);
  if (plan.reference.substeps * plan.reference.iterations < 2)
    throw Error("--reference: needs at least 2 sweeps per step (it is checked at half its budget)");
  const std::vector<StudySolver> reference = solver_list(o.reference_solver.empty() ? "colored" : o.reference_solver);
  if (reference.size() != 1) throw Error("--reference-solver: give one solver");
  plan.reference_solver = reference.front();
  // --quick checks its reference but does not raise it (the smoke test's time stays that of one reference run).
  if (o.quick) plan.reference_max = plan.reference.substeps * plan.reference.iterations;
  if (o.reference_max > 0) plan.reference_max = o.reference_max;
  plan.reference_max = std::max(plan.reference_max, plan.reference.substeps * plan.reference.iterations);
  plan.reference_seconds = o.reference_seconds > 0.0 ? o.reference_seconds : o.quick ? 2.0 : 120.0;
  if (!(o.target > 0.0)) throw Error("--target: must be above 0 (an error in %)");
  plan.target = o.target;
  plan.variants = split_list(o.variants);
  for (const std::string& v : plan.variants) {
    const auto& names = variant_names();
    if (std::find(names.begin(), names.end(), v) == names.end()) {
      std::string valid;
      for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
      throw Error("--variants: unknown variant \"" + v + "\" (valid: " + valid + ")");
    }
  }
  if (o.format != "table" && o.format != "csv" && o.format != "json")
    throw Error("--format: \"" + o.format + "\" is not table, csv or json");
  plan.format = o.format;
  if (o.shard == "auto") slurm_shard(plan.shard, plan.shards);
  else if (!o.shard.empty()) {
    const std::size_t slash = o.shard.find('/');
    if (slash == std::string::npos || !parse_int(o.shard.substr(0, slash), plan.shard) ||
        !parse_int(o.shard.substr(slash + 1), plan.shards) || plan.shards < 1 || plan.shard < 1 ||
        plan.shard > plan.shards)
      throw Error("--shard: \"" + o.shard + "\" is not I/N with 1 <= I <= N (such as 2/3)");
  }
  plan.json = o.json;
  plan.plots = o.plots;
  plan.commit = o.commit;
  return plan;
}

}  // namespace pbd::cli
