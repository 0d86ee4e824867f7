// libFuzzer target: parse_scene on arbitrary bytes, then the double and float worlds of what it accepts. A pbd::Error
// is the expected answer to bad input; anything else (a crash, another exception, a sanitizer report, a hang, a huge
// allocation, a scene accepted but refused by build_world<double>) is a bug.
#include "pbd/error.hpp"
#include "pbd/io/build_world.hpp"
#include "pbd/io/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  pbd::Scene scene;
  try {
    // A folder that does not exist: a relative "obj" path never reaches a real file.
    scene = pbd::parse_scene(text, "/nonexistent-pbd-fuzz/scene.json");
  } catch (const pbd::Error&) {
    return 0;
  }
  pbd::build_world<double>(scene.world);  // not caught: every accepted scene builds in double
  try {
    pbd::build_world<float>(scene.world);
  } catch (const pbd::Error&) {  // a value beyond float range (a position of 1e300) is refused
  }
  return 0;
}
