// libFuzzer target: parse_obj on arbitrary bytes. A pbd::Error is the expected answer to bad input; anything else
// (a crash, another exception, a sanitizer report, a hang, a huge allocation) is a bug, and so is an accepted input
// whose mesh differs from tinyobjloader's reading of the same statements (vertex bits, faces).
#include "pbd/error.hpp"
#include "pbd/io/obj_loader.hpp"
#include "tinyobj_reference.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  pbd::TriangleMesh mesh;
  try {
    mesh = pbd::parse_obj(text, "fuzz.obj");
  } catch (const pbd::Error&) {
    return 0;
  }
  const auto reference = pbd::test::tinyobj_mesh(text);
  if (!reference || !pbd::test::same_mesh(*reference, mesh)) std::abort();
  return 0;
}
