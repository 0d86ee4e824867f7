// The installed header's version is the CMake package's (PBD_PACKAGE_VERSION, from pbdConfigVersion.cmake).
#include <pbd/version.hpp>

#include <cstdio>
#include <string_view>

static_assert(std::string_view(PBD_VERSION_STRING) == PBD_PACKAGE_VERSION,
              "pbd/version.hpp and the CMake package disagree on the version");

int main() { std::printf("pbd::version %s\n", pbd::version); }
