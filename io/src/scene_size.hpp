#pragma once
// A scene's size limits, and the pass that sizes every body from its JSON before any body is built, so that a scene
// over a limit is refused at once, naming the body, instead of after gigabytes of generated bodies. Private to pbd::io.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace pbd::detail {

#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
inline constexpr long kMaxSceneParticles = 100'000;        // fuzz builds (tests/fuzz): accepted inputs stay small
inline constexpr std::uint64_t kMaxSceneConstraints = 1'000'000;
#else
inline constexpr long kMaxSceneParticles = 50'000'000;       ///< particles of all bodies together
inline constexpr std::uint64_t kMaxSceneConstraints = 200'000'000;  ///< constraints of all bodies together
#endif

/// Sizes each element of root["bodies"] from its keys (a cloth's resolution, a rope's particles, a generator's
/// level, ...): its particles and the constraints it asks for, at most. Throws pbd::Error naming `file` and the
/// body's size key when the bodies up to it pass either limit. Values it cannot read are left to the strict reader
/// (they count as zero here); an OBJ mesh is sized when it is loaded.
void check_scene_size(const nlohmann::json& root, const std::string& file);

}  // namespace pbd::detail
