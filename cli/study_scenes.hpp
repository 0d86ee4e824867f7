#pragma once
// The scenes `pbd study` runs, those of every command (scene_dir.hpp: built-in scenes, scene files and the
// generated ones of generated_scenes.hpp), each as a variant (scene_variants.hpp), which edits its JSON before it is
// parsed; and the closed forms the quasi-static generated scenes and the fibers on a curve are measured against.
#include "generated_scenes.hpp"
#include "scene_dir.hpp"
#include "study_record.hpp"

#include "pbd/world.hpp"

#include <string>
#include <vector>

namespace pbd::cli {

/// Whether `name` is a generated hanging cloth cloth<N> or cloth<N>-rest (and not a built-in scene or a file).
bool is_generated_cloth(const std::string& name);

/// Loads a built-in scene, a generated one or a scene file as `variant` (scene_variants.hpp; "plain": as it is);
/// throws pbd::Error listing the valid names, or naming the variant that does not apply.
Scene load_study_scene(const std::string& name_or_file, const std::string& variant = "plain");

/// The variants the study runs on a scene: of `requested`, those that apply to it (plain always); with `requested`
/// empty, on a generated scene every variant that applies (a built-in scene or file: plain), leaving out (with a
/// note on stderr) one whose scene keys this build does not parse, unless `keep_unparsed`. An explicitly requested
/// variant that does not parse throws the parser's pbd::Error when the scene is loaded.
std::vector<std::string> study_variants(const std::string& name_or_file, const std::vector<std::string>& requested,
                                        bool keep_unparsed = false);

/// Throws pbd::Error (listing the valid names) unless `name_or_file` names a scene load_study_scene can load.
void check_study_scene(const std::string& name_or_file);

/// The closed-form answer of a quasi-static generated scene ("" kind: none): what its error is measured against,
/// and from which step on it is averaged (the settled part of the run).
struct KnownAnswer {
  std::string kind;          ///< "rest" (cloth<N>-rest: stretch → 0), "chain" (chain30: extension α·T_k), "curve"
                             ///< (a scene with fibers on a stress–strain curve: their forces on it), or ""
  int links = 0;             ///< chain: links (the particles below the pin)
  double compliance = 0.0;   ///< chain: α, m/N
  double link_mass = 0.0;    ///< chain: mass of each particle, kg
  double gravity = 0.0;      ///< chain: |g|, m/s²
  double rest_length = 0.0;  ///< chain: rest length of a link, m
  double settled_motion = 0.0;  ///< RMS displacement (m) over the averaged steps below which the run has settled
};

/// The known answer of a scene by its name (kind "" for a scene that has none).
KnownAnswer known_answer(const std::string& name);
/// The known answer of a scene the study runs: its name's, or "curve" where scene_info found fibers on a curve.
KnownAnswer known_answer(const SceneInfo& info);

/// Whether `world` has fibers or tet fibers in a set with a stress–strain curve: its error is then the curve's
/// (curve_errors).
template <class Real> bool has_curve(const World<Real>& world);
/// Each such fiber's tension, or tet fiber's stress (from λ, World::material_readings), against its curve's at its
/// elastic strain, in % of its set's scale (the curve at yield, else at rupture, else at unit strain), as the
/// measure "curve_pct" (RMS and maximum over those that have a force, and those the last step broke, at their
/// break; 0 when there are none). Before a step none has a force.
template <class Real> Errors curve_errors(const World<Real>& world);

/// For a chain: each link's extension against α·T_k, in % of α·T_k (RMS and maximum over the links), as the
/// measure "extension_pct" (study_record.hpp's known_answer_measures() labels it); nothing for other kinds. `x`
/// holds the chain's particles first, the pin first.
Errors known_answer_errors(const KnownAnswer& answer, const Matrix3X<double>& x);

}  // namespace pbd::cli
