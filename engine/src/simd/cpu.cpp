#include "cpu.hpp"

#include <cstdlib>
#include <cstring>

namespace pbd::detail {

bool avx2_enabled() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool on = [] {
    if (const char* env = std::getenv("PBD_SIMD"); env && std::strcmp(env, "sse2") == 0) return false;
    __builtin_cpu_init();
    return bool(__builtin_cpu_supports("avx2"));
  }();
  return on;
#else
  return false;
#endif
}

}  // namespace pbd::detail
