// libFuzzer target: parse_scene on arbitrary bytes. A pbd::Error is the expected answer to bad input; anything else
// (a crash, another exception, a sanitizer report, a hang, a huge allocation) is a bug.
#include "pbd/error.hpp"
#include "pbd/io/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // A folder that does not exist: a relative "obj" path never reaches a real file.
    pbd::parse_scene(text, "/nonexistent-pbd-fuzz/scene.json");
  } catch (const pbd::Error&) {
  }
  return 0;
}
