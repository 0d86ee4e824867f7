// `pbd study`: the speed-vs-error study, and `pbd study merge` that joins the reports of its shards. The study
// runs scenes × sweep budgets × splits × solvers × threads (study_session.hpp says in what order); for each
// combination it measures the wall time per step (median, minimum, maximum and CV of interleaved timed runs) and
// the error reached in physical units (each scene's primary measure, every constraint type's, the distance from a
// converged reference), and reports them as a table, CSV or JSON on stdout, a JSON file and plots (plot_script.hpp).
#include "commands.hpp"
#include "data_dir.hpp"
#include "option_rules.hpp"
#include "pbd/error.hpp"
#include "pbd/io/atomic_file.hpp"
#include "plot_script.hpp"
#include "study_options.hpp"
#include "report_reader.hpp"
#include "study_report.hpp"
#include "study_session.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <unistd.h>

namespace pbd::cli {
namespace {

// Writes `text` to `file` whole or not at all (write_file_atomically), creating its folder; errors name `flag`.
void write_file(const std::filesystem::path& file, const std::string& text, const std::string& flag) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) throw Error(flag + ": " + file.parent_path().string() + ": cannot create the folder (" + ec.message() + ")");
  try {
    write_file_atomically(file, text);
  } catch (const Error& e) {
    throw Error(flag + ": " + e.what());
  }
}

// stdout in the chosen format, the JSON file, the plots.
void output(const Report& report, const std::string& format, const std::string& json_file, const std::string& plots,
            PlotTools tools) {
  std::ostringstream text;
  const nlohmann::json doc = report_json(report);
  if (format == "json") text << doc.dump(1) << "\n";
  else if (format == "csv") print_csv(text, report);
  else print_table(text, report);
  std::cout << text.str();
  std::cout.flush();
  if (!std::cout) throw Error("cannot write the report to standard output");
  for (const auto& w : report.study["warnings"])
    std::fprintf(stderr, "pbd study: WARNING: %s\n", w.get<std::string>().c_str());
  std::filesystem::path json = json_file;
  if (json.empty() && !plots.empty()) json = std::filesystem::path(plots) / "study.json";
  if (!json.empty()) {
    write_file(json, doc.dump(1) + "\n", "--json");
    std::fprintf(stderr, "pbd study: wrote %s\n", json.string().c_str());
  }
  if (plots.empty()) return;
  run_plot_script(tools, json, plots);
}

// --plot-script and --python, of `pbd study` and of `pbd study merge`. Their environment variables are read by
// plot_tools(), not by CLI11, so that only the command line counts as asking for them (option_rules.hpp).
void add_plot_options(CLI::App* cmd, PlotTools& tools) {
  cmd->add_option("--plot-script", tools.script,
                  "The plot script of --plots (default: $PBD_PLOT_SCRIPT, else share/pbd/plot_study.py beside the "
                  "program's folder)");
  cmd->add_option("--python", tools.python,
                  "The Python 3 with matplotlib that runs the plot script (default: $PBD_PYTHON, else python3 on "
                  "PATH)");
}

// The tools as given, the environment filling in what the command line did not give; refuses them without --plots.
PlotTools plot_tools(const CLI::App& cmd, PlotTools tools) {
  const std::string why = "they only draw the plots";
  refuse_without(cmd, "--plot-script", "--plots", why);
  refuse_without(cmd, "--python", "--plots", why);
  auto env = [](const char* name) {
    const char* v = std::getenv(name);
    return v ? std::string(v) : std::string();
  };
  if (tools.script.empty()) tools.script = env("PBD_PLOT_SCRIPT");
  if (!given(cmd, "--python")) tools.python = env("PBD_PYTHON");
  if (tools.python.empty()) tools.python = "python3";
  tools.default_script = data_dir() / "plot_study.py";
  return tools;
}

// The options of `pbd study` that do nothing in the mode or with the options chosen are refused.
void check_study_rules(const CLI::App& cmd) {
  refuse_without(cmd, "--split", "--scaling", "only the scaling study runs one split; the main study runs every "
                 "split of each --budgets");
  const std::string scaling_why = "the scaling study runs one --split per scene, with no reference and no variants";
  for (const char* option : {"--budgets", "--reference", "--reference-solver", "--reference-max", "--reference-seconds",
                             "--variants", "--target"})
    refuse_with(cmd, option, given(cmd, "--scaling"), "--scaling", scaling_why);
  for (const char* option : {"--json", "--plots", "--format", "--commit", "--plot-script", "--python"})
    refuse_with(cmd, option, given(cmd, "--estimate"), "--estimate", "it prints the plan and runs nothing");
}

// `pbd study merge` takes none of `pbd study`'s options: given before `merge` they would be ignored.
void refuse_study_options(const CLI::App& study) {
  for (const CLI::Option* option : study.get_options())
    if (option->count() > 0 && option->get_name() != "--help")
      throw Error("merge: " + option->get_name() + " is an option of `pbd study`, not of `pbd study merge` (its "
                  "options --json, --plots, --format, --plot-script, --python and --allow-mixed-machines go after "
                  "`merge`)");
}

struct MergeOptions {
  std::vector<std::string> files;
  std::string json, plots, format = "table";
  bool allow_mixed_machines = false;
};

}  // namespace

void add_study_command(CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "The speed-vs-error study: time per step and error reached for scenes x sweep budgets (every split "
               "into substeps x iterations) x solvers x threads; table/CSV/JSON on stdout, JSON report, plots");
  cmd->add_option("--scene", o->scenes,
                  "Built-in scene (pbd list), generated cloth<N> (hanging cloth, 1 s), cloth<N>-rest (damped to rest), "
                  "chain30 (compliant chain against alpha*T), or a scene JSON file; repeatable or comma-separated "
                  "(default: the built-in scenes but pile, and cloth30, cloth100, cloth300, cloth30-rest, chain30 "
                  "(--quick: not cloth300); --scaling: cloth30, cloth100, cloth300, cloth1000)");
  cmd->add_option("--solvers", o->solvers,
                  "Comma-separated: " + solver_names() + ", or any but serial with +chebyshev (splits of 4 or more iterations; default "
                  "serial,colored,jacobi,block; --scaling: colored,jacobi,block)");
  cmd->add_option("--threads", o->threads,
                  "Comma-separated thread counts; serial solvers run once, on 1 (default 1,2; --scaling: 1 to the "
                  "machine's cores)");
  cmd->add_option("--budgets", o->budgets,
                  "Comma-separated sweeps per step N; each runs every split S x I with S x I = N up to 8, and N x 1 "
                  "above (default 1,2,4,8,16,32,64,128,256, up to 8 on scenes other than the generated ones and those "
                  "whose fibers have a curve; --quick 2,4)");
  cmd->add_option("--split", o->split, "SUBSTEPSxITERATIONS of --scaling (default 1x10)");
  cmd->add_option("--steps", o->steps, "Steps per run (default: each scene's own; --quick at most 20)")
      ->check(CLI::Range(1, kMaxSteps));
  cmd->add_option("--precision", o->precision, "float or double")->capture_default_str();
  cmd->add_option("--repeats", o->repeats, "Timed runs per combination after the warm-up (default 3; --quick 1)")
      ->check(CLI::Range(1, kMaxRepeats));
  cmd->add_option("--reference", o->reference,
                  "SUBSTEPSxITERATIONS the reference starts at (double; default twice the largest budget, as "
                  "substeps: 512x1; --quick 8x1); while it is not converged (its change at half its budget above a "
                  "tenth of the smallest error it is compared with) its substeps double");
  cmd->add_option("--reference-solver", o->reference_solver,
                  "The reference's solver (default colored: bitwise identical on any thread count, run on the most "
                  "threads)");
  cmd->add_option("--reference-max", o->reference_max,
                  "The most sweeps per step the reference is raised to (default 4096; --quick: not raised)")
      ->check(CLI::Range(2, kMaxReferenceBudget));
  cmd->add_option("--reference-seconds", o->reference_seconds,
                  "The longest one scene's reference may take, from the estimate of its next doubling (default 120; "
                  "--quick 2)")
      ->check(CLI::Range(0.0, kMaxReferenceSeconds));
  cmd->add_option("--variants", o->variants,
                  "Comma-separated: plain, tethers, hierarchy, tethers+hierarchy (default: every one that applies "
                  "to each scene and that this build parses); a variant edits the scene JSON before parsing");
  cmd->add_option("--target", o->target,
                  "The headline's error in % of the primary measure, run-averaged (default 1): the fastest point "
                  "at or below it per scene, variant, solver and threads")
      ->check(CLI::Range(1e-9, 1e9));
  cmd->add_option("--format", o->format, "What goes to stdout: table, csv or json")->capture_default_str();
  cmd->add_option("--json", o->json, "Write the JSON report to FILE");
  cmd->add_option("--plots", o->plots,
                  "Write plots (PNG and SVG) and summary.md to DIR with plot_study.py (and the JSON to "
                  "DIR/study.json if no --json)");
  cmd->add_option("--shard", o->shard,
                  "Run only part I of N (I/N) of the combinations; join the parts' --json reports with `pbd study "
                  "merge`. auto: I and N from a Slurm job array (SLURM_ARRAY_TASK_ID of MIN..MAX or COUNT)");
  cmd->add_option("--commit", o->commit,
                  "The commit the program was built from, for the report (default: $PBD_COMMIT, which scripts/study "
                  "sets to `git describe`, else unknown)");
  auto plot = std::make_shared<PlotTools>();
  add_plot_options(cmd, *plot);
  cmd->add_flag("--quick", o->quick,
                "Smoke test: budgets 2,4, at most 20 steps, 1 timed run, an 8x1 reference, no cloth300 (explicit "
                "options win)");
  cmd->add_flag("--estimate", o->estimate,
                "Print what the study would run and its estimated time per scene (from a cost model of this kind "
                "of machine, before anything is timed), and run nothing");
  cmd->add_flag("--scaling", o->scaling,
                "Scaling study: strong scaling over thread counts with the same-run shared-nothing reference, and "
                "size scaling over cloth30 .. cloth1000, at one split");

  auto m = std::make_shared<MergeOptions>();
  CLI::App* merge = cmd->add_subcommand("merge", "Join the JSON reports of a study's shards into one report");
  merge->add_option("reports", m->files, "The shards' JSON reports (--shard I/N --json FILE)")->required();
  merge->add_option("--json", m->json, "Write the merged JSON report to FILE");
  merge->add_option("--plots", m->plots, "Write plots of the merged report to DIR");
  merge->add_option("--format", m->format, "What goes to stdout: table, csv or json")->capture_default_str();
  merge->add_flag("--allow-mixed-machines", m->allow_mixed_machines,
                  "Join shards that ran on machines of another CPU or core count (the merged report lists each "
                  "machine); commit, version, build and options must still agree");
  auto merge_plot = std::make_shared<PlotTools>();
  add_plot_options(merge, *merge_plot);
  merge->callback([m, merge, cmd, merge_plot] {
    refuse_study_options(*cmd);
    refuse_empty_values(*merge);
    if (m->format != "table" && m->format != "csv" && m->format != "json")
      throw Error("--format: \"" + m->format + "\" is not table, csv or json");
    const PlotTools tools = plot_tools(*merge, *merge_plot);
    if (!m->plots.empty()) check_plot_tools(tools);  // before the merge, as before a study
    std::vector<Report> parts;
    for (const std::string& f : m->files) parts.push_back(read_report(f));
    output(merge_reports(parts, m->files, {m->allow_mixed_machines}), m->format, m->json, m->plots, tools);
  });
  cmd->callback([o, merge, cmd, plot] {
    if (merge->parsed()) return;
    refuse_empty_values(*cmd);
    check_study_rules(*cmd);
    const PlotTools tools = plot_tools(*cmd, *plot);
    if (o->commit.empty())
      if (const char* commit = std::getenv("PBD_COMMIT")) o->commit = commit;
    const StudyPlan plan = make_plan(*o);
    if (plan.estimate) return estimate_study(plan);
    // The plot script and its Python are checked before the first point, not after the whole study.
    if (!plan.plots.empty()) check_plot_tools(tools);
    output(run_study(plan), plan.format, plan.json, plan.plots, tools);
  });
}

}  // namespace pbd::cli
