#pragma once
// The options a study compares on one scene ("variants"): the plain scene, long-range attachments (tethers) and
// hierarchical PBD, alone and together. A variant edits the scene's JSON before it is parsed, so it works on the
// generated cloths and on any scene file alike: "tethers": true on every cloth, rope or mesh body with pinned
// particles, "hierarchy": true at the top level (the scene keys of docs/scene-format.md).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pbd::cli {

/// Every variant, in the order the study runs them: plain, tethers, hierarchy, tethers+hierarchy.
const std::vector<std::string>& variant_names();

/// Whether `variant` changes `scene` (a scene's JSON): tethers need a cloth (pin not "none"), rope or mesh body
/// with pinned particles and stretch that is not compliant (XPBD α > 0); hierarchy needs a cloth, rope or mesh body with stretch constraints; plain always applies.
/// Throws pbd::Error for a name not in variant_names().
bool variant_applies(const nlohmann::json& scene, const std::string& variant);

/// `scene` with `variant` applied (plain: unchanged). Bodies that already state "tethers", and a scene that already
/// states "hierarchy", keep their own. Throws pbd::Error when the variant does not apply or is unknown.
nlohmann::json apply_variant(nlohmann::json scene, const std::string& variant);

}  // namespace pbd::cli
