// `pbd color SCENE`: colors a scene's constraints the way the colored solver will and prints the statistics
// (colors, lower bound, batch sizes, time) per constraint type and overall; optionally as JSON.
#include "commands.hpp"
#include "pbd/io/atomic_file.hpp"
#include "pbd/io/build_world.hpp"
#include "scene_dir.hpp"

#include <nlohmann/json.hpp>
#include <pbd/graph_coloring/graph_coloring.hpp>

#include <algorithm>
#include <iostream>
#include <memory>

namespace pbd::cli {
namespace {

struct ColorOptions {
  std::string scene;
  std::string algorithm = "input";
  bool balance = true;
  std::string json;
};

nlohmann::json to_json(const coloring::NamedStats& row) {
  const coloring::Stats& s = row.stats;
  return {{"name", row.name},           {"items", s.num_items},         {"colors", s.num_colors},
          {"lower_bound", s.lower_bound}, {"wide", s.num_wide},         {"min_batch", s.min_batch},
          {"mean_batch", s.mean_batch}, {"max_batch", s.max_batch},     {"max_over_mean", s.max_over_mean},
          {"seconds", s.seconds}};
}

void run(const ColorOptions& o) {
  const Scene scene = load_builtin_scene(o.scene);
  const auto algorithm = coloring::parse_algorithm(o.algorithm);
  coloring::Options options;
  options.algorithm = *algorithm;
  options.balance = o.balance;
  const World<double> world = build_world<double>(scene.world);
  coloring::Stats all;
  std::uint64_t batches = 0;
  std::vector<coloring::NamedStats> rows = world.color_statistics(options);
  for (const coloring::NamedStats& row : rows) {
    const coloring::Stats& s = row.stats;
    // Overall: the types are solved one after the other, so colors, bounds, items and time add up.
    all.num_items += s.num_items;
    all.num_colors += s.num_colors;
    all.num_wide += s.num_wide;
    all.lower_bound += s.lower_bound;
    all.seconds += s.seconds;
    all.min_batch = batches ? std::min(all.min_batch, s.min_batch) : s.min_batch;
    all.max_batch = std::max(all.max_batch, s.max_batch);
    batches += s.num_colors - s.num_wide;
  }
  if (batches) {
    all.mean_batch = double(all.num_items - all.num_wide) / double(batches);
    all.max_over_mean = all.max_batch / all.mean_batch;
  }
  rows.push_back({"overall", all});
  std::cout << "# scene " << scene.name << " (" << scene.source << "), " << world.num_particles() << " particles, "
            << "algorithm " << coloring::name(*algorithm) << (o.balance ? ", balanced" : ", not balanced") << "\n"
            << coloring::format_stats(rows);
  if (!o.json.empty()) {
    nlohmann::json out = {{"scene", scene.name},
                          {"particles", world.num_particles()},
                          {"algorithm", std::string(coloring::name(*algorithm))},
                          {"balance", o.balance},
                          {"types", nlohmann::json::array()}};
    for (const auto& r : rows) out["types"].push_back(to_json(r));
    try {
      write_file_atomically(o.json, out.dump(2) + "\n");
    } catch (const Error& e) {
      throw Error(std::string("--json: ") + e.what());
    }
  }
}

}  // namespace

void add_color_command(CLI::App& app) {
  auto o = std::make_shared<ColorOptions>();
  CLI::App* cmd = app.add_subcommand("color", "Color a scene's constraints and print the statistics");
  cmd->add_option("scene", o->scene, "Scene name (pbd list: built-in or generated) or scene JSON file")->required();
  std::vector<std::string> names;
  for (coloring::Algorithm a : coloring::all_algorithms) names.emplace_back(coloring::name(a));
  cmd->add_option("--algorithm", o->algorithm, "Coloring algorithm")->check(CLI::IsMember(names))->capture_default_str();
  cmd->add_flag("!--no-balance", o->balance, "Skip the balancing pass");
  cmd->add_option("--json", o->json, "Also write the statistics to this JSON file");
  cmd->callback([o] { run(*o); });
}

}  // namespace pbd::cli
