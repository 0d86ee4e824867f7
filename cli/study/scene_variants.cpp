#include "scene_variants.hpp"

#include "pbd/error.hpp"

#include <algorithm>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

std::string type_of(const json& body) {
  const auto it = body.find("type");
  return it != body.end() && it->is_string() ? it->get<std::string>() : "";
}

// A cloth pins its corners unless "pin" says "none"; a rope pins its first particle; a mesh pins what it lists.
bool has_pins(const json& body) {
  const std::string type = type_of(body);
  if (type == "cloth") return body.value("pin", std::string("corners")) != "none";
  if (type == "rope") return true;
  if (type == "mesh") {
    const auto it = body.find("pinned");
    return it != body.end() && it->is_array() && !it->empty();
  }
  return false;
}

// Tethers hold a particle within its rest distance of the pins, so they belong on bodies whose stretch is meant to
// hold its rest length: on compliant (XPBD) stretch they would stop the stretch that the compliance asks for (a
// compliant chain would hang at its rest length, not α·T longer).
bool takes_tethers(const json& body) {
  if (!has_pins(body)) return false;
  const auto stretch = body.find("stretch");
  if (stretch == body.end() || !stretch->is_object()) return true;
  const auto compliance = stretch->find("compliance");
  return compliance == stretch->end() || !compliance->is_number() || compliance->get<double>() == 0.0;
}

bool has_stretch(const json& body) {
  const std::string type = type_of(body);
  return (type == "cloth" || type == "rope" || type == "mesh") && body.contains("stretch");
}

const json& bodies_of(const json& scene) {
  static const json none = json::array();
  const auto it = scene.find("bodies");
  return it != scene.end() && it->is_array() ? *it : none;
}

bool wants(const std::string& variant, const char* option) {
  return variant == option || variant == "tethers+hierarchy";
}

void check_name(const std::string& variant) {
  const auto& names = variant_names();
  if (std::find(names.begin(), names.end(), variant) != names.end()) return;
  std::string valid;
  for (const std::string& n : names) valid += (valid.empty() ? "" : ", ") + n;
  throw Error("--variants: unknown variant \"" + variant + "\" (valid: " + valid + ")");
}

}  // namespace

const std::vector<std::string>& variant_names() {
  static const std::vector<std::string> names{"plain", "tethers", "hierarchy", "tethers+hierarchy"};
  return names;
}

bool variant_applies(const json& scene, const std::string& variant) {
  check_name(variant);
  const json& bodies = bodies_of(scene);
  if (wants(variant, "tethers") && std::none_of(bodies.begin(), bodies.end(), takes_tethers)) return false;
  if (wants(variant, "hierarchy") && std::none_of(bodies.begin(), bodies.end(), has_stretch)) return false;
  return true;
}

json apply_variant(json scene, const std::string& variant) {
  if (!variant_applies(scene, variant))
    throw Error("variant " + variant + ": the scene \"" + scene.value("name", std::string("?")) +
                "\" has no body it applies to");
  if (wants(variant, "tethers"))
    for (json& body : scene["bodies"])
      if (takes_tethers(body) && !body.contains("tethers")) body["tethers"] = true;
  if (wants(variant, "hierarchy") && !scene.contains("hierarchy")) scene["hierarchy"] = true;
  return scene;
}

}  // namespace pbd::cli
