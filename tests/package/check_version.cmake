# cmake -P script: the version is written once, in project(pbd VERSION ...); the files that must repeat it literally
# agree with it. CITATION.cff's `version:` (the Debian package, the CMake package, pbd/version.hpp and setup.py take
# theirs from CMake).
file(STRINGS ${CITATION} lines REGEX "^version:")
if(NOT lines STREQUAL "version: ${VERSION}")
  message(FATAL_ERROR "${CITATION}: '${lines}' is not 'version: ${VERSION}', the version in CMakeLists.txt's "
                      "project(pbd VERSION ...)")
endif()
message("CITATION.cff has version ${VERSION}, as CMakeLists.txt")
