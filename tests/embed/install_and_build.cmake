# cmake -P script: installs the build tree into WORK_DIR/prefix and builds two hosts against it as users would.
# - examples/embed, configured with no build type: it picks Release itself (so pbd's package does not warn), builds,
#   and runs its cloth.
# - tests/embed/version_consumer: find_package(pbd MAJOR.MINOR) of PBD_VERSION is accepted and the next minor version
#   is refused; the program sees the package's version in pbd/version.hpp (a static_assert) and prints pbd::version.
#   With no build type, pbd's package warns that the host compiles unoptimized; with Release, or -O2 in
#   CMAKE_CXX_FLAGS, it does not.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

# run(OUT EXPECT_STATUS command...): runs the command; OUT is its stdout and stderr.
function(run out_var expect)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if((expect STREQUAL "0" AND NOT rc EQUAL 0) OR (expect STREQUAL "fail" AND rc EQUAL 0))
    message(FATAL_ERROR "status ${rc} (expected ${expect}): ${ARGN}\n${out}\n${err}")
  endif()
  set(${out_var} "${out}${err}" PARENT_SCOPE)
endfunction()

# check(TEXT REGEX MATCH|NOMATCH WHAT)
function(check text regex want what)
  if(text MATCHES "${regex}")
    set(found MATCH)
  else()
    set(found NOMATCH)
  endif()
  if(NOT found STREQUAL want)
    message(FATAL_ERROR "${what}: expected ${want} of '${regex}' in:\n${text}")
  endif()
endfunction()

set(unoptimized "pbd: CMAKE_BUILD_TYPE is not set")
run(out 0 ${CMAKE_COMMAND} --install ${PBD_BUILD_DIR} --prefix ${prefix})

# The example, with no build type given.
set(example ${WORK_DIR}/example)
run(out 0 ${CMAKE_COMMAND} -S ${PBD_EXAMPLE_DIR} -B ${example} -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix})
check("${out}" "${unoptimized}" NOMATCH "examples/embed must choose Release itself")
file(STRINGS ${example}/CMakeCache.txt build_type REGEX "^CMAKE_BUILD_TYPE:")
check("${build_type}" "=Release$" MATCH "examples/embed's default build type")
run(out 0 ${CMAKE_COMMAND} --build ${example})
run(out 0 ${example}/embed)
check("${out}" "lowest particle z" MATCH "examples/embed's output")
message("${out}")

# The version: accepted as MAJOR.MINOR, refused as the next minor, seen by the compiler.
string(REGEX MATCH "^([0-9]+)\\.([0-9]+)" major_minor "${PBD_VERSION}")
math(EXPR next "${CMAKE_MATCH_2} + 1")
set(next_minor ${CMAKE_MATCH_1}.${next})
set(consumer ${WORK_DIR}/version_consumer)
set(configure ${CMAKE_COMMAND} -S ${PBD_VERSION_CONSUMER_DIR} -B ${consumer} -G ${GENERATOR}
              -DCMAKE_PREFIX_PATH=${prefix})
run(out 0 ${configure} -DPBD_REQUEST=${major_minor})
check("${out}" "${unoptimized}" MATCH "pbd's package with no build type")
run(out 0 ${CMAKE_COMMAND} --build ${consumer})
run(out 0 ${consumer}/version_consumer)
check("${out}" "^pbd::version ${PBD_VERSION}\n$" MATCH "pbd::version as the host sees it")
message("${out}")
run(out 0 ${configure} -DPBD_REQUEST=${major_minor} -DCMAKE_BUILD_TYPE=Release)
check("${out}" "${unoptimized}" NOMATCH "pbd's package with CMAKE_BUILD_TYPE=Release")
file(REMOVE_RECURSE ${consumer})
run(out 0 ${configure} -DPBD_REQUEST=${major_minor} -DCMAKE_CXX_FLAGS=-O2)
check("${out}" "${unoptimized}" NOMATCH "pbd's package with no build type but -O2 in CMAKE_CXX_FLAGS")
file(REMOVE_RECURSE ${consumer})
run(out fail ${configure} -DPBD_REQUEST=${next_minor})
check("${out}" "version: ${PBD_VERSION}" MATCH "find_package(pbd ${next_minor}) must name the version found")
message("find_package(pbd ${major_minor}) found ${PBD_VERSION}; find_package(pbd ${next_minor}) refused it")
