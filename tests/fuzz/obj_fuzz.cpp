// libFuzzer target: parse_obj on arbitrary bytes. A pbd::Error is the expected answer to bad input; anything else
// (a crash, another exception, a sanitizer report, a hang, a huge allocation) is a bug.
#include "pbd/error.hpp"
#include "pbd/io/obj_loader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    pbd::parse_obj(text, "fuzz.obj");
  } catch (const pbd::Error&) {
  }
  return 0;
}
