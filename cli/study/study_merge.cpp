// `pbd study merge`: the shards' reports joined into one (study_report.hpp's merge_reports).
#include "study_report.hpp"

#include "pbd/error.hpp"
#include "scene_variants.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

namespace pbd::cli {

using json = nlohmann::json;

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

// Each name's first index in `names`.
std::map<std::string, std::size_t> first_positions(const std::vector<std::string>& names) {
  std::map<std::string, std::size_t> out;
  for (std::size_t i = 0; i < names.size(); ++i) out.emplace(names[i], i);
  return out;
}
// The position of `name`, or after every other when it has none.
std::size_t position_in(const std::map<std::string, std::size_t>& positions, const std::string& name) {
  const auto it = positions.find(name);
  return it == positions.end() ? std::numeric_limits<std::size_t>::max() : it->second;
}

}  // namespace

Report merge_reports(const std::vector<Report>& parts, const std::vector<std::string>& sources,
                     const MergeRules& rules) {
  if (parts.empty()) throw Error("merge: no reports given");
  if (sources.size() != parts.size())
    throw Error("merge: " + std::to_string(parts.size()) + " reports but " + std::to_string(sources.size()) +
                " file names");
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
  // Each scene and reference once (every shard that touched a scene has them, the same bits); every record.
  std::set<std::string> scenes, references;
  for (const Report& part : parts) {
    seconds += part.study.value("seconds", 0.0);
    for (const SceneInfo& s : part.scenes)
      if (scenes.insert(s.name).second) out.scenes.push_back(s);
    for (const Reference& r : part.references)
      if (references.insert(r.scene).second) out.references.push_back(r);
    for (const SharedNothing& s : part.shared_nothing) out.shared_nothing.push_back(s);
    for (const Record& r : part.records) out.records.push_back(r);
  }
  // Scenes in the order of the options' scenes; a scene's variants follow it in the order one run takes them
  // (scene_variants.hpp), whichever shard ran them. Positions are looked up, so that sorting stays n log n.
  const auto scene_order = first_positions(options.at("scenes").get<std::vector<std::string>>());
  const auto variant_order = first_positions(variant_names());
  auto position = [&](const SceneInfo& s) {
    return std::make_pair(position_in(scene_order, s.base.empty() ? s.name : s.base),
                          position_in(variant_order, s.variant));
  };
  std::stable_sort(out.scenes.begin(), out.scenes.end(),
                   [&](const SceneInfo& a, const SceneInfo& b) { return position(a) < position(b); });
  // Records, references and shared-nothing runs in the order of their scenes, then as the shards ran them.
  std::map<std::string, std::size_t> scene_rank;
  for (std::size_t i = 0; i < out.scenes.size(); ++i) scene_rank.emplace(out.scenes[i].name, i);
  auto rank = [&](const std::string& scene) { return position_in(scene_rank, scene); };
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


}  // namespace pbd::cli
