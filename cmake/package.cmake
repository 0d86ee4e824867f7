# The Debian package: `cd build/release && cpack` makes pbd_<version>_<arch>.deb from everything cmake/install.cmake
# installs, under /usr: the static libraries, headers and CMake package (/usr/lib/cmake/pbd), `pbd` with its scenes
# and plot script (/usr/share/pbd), and the Python module for /usr/bin/python3 (/usr/lib/python3/dist-packages).
# The libraries are static and the program and the module link only Debian's shared libraries, so nothing carries
# an RPATH: the files work wherever they are unpacked (`dpkg -x`; test cli_installed, tests/cli/check_install.py).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME pbd)
set(CPACK_PACKAGE_VENDOR "the pbd authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "data-parallel Position Based Dynamics engine (library, program, Python)")
set(CPACK_PACKAGE_DESCRIPTION "\
A multithreaded Position Based Dynamics engine in C++20 with XPBD compliance: graph-colored parallel
Gauss-Seidel, Jacobi and block solvers, tethers and hierarchical PBD, soft bodies and fibers.
This package holds the static C++ libraries with their CMake package (find_package(pbd)), the pbd
program with its built-in scenes, and the Python module pbd for python3.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(PBD_PACKAGE_MAINTAINER "the pbd authors <maintainers@users.noreply.h-seed-66014f24.example>" CACHE STRING
    "The Maintainer field of the Debian package")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${PBD_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # pbd_0.1.0_amd64.deb: version from project(), architecture from dpkg
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)    # dpkg-deb's own default; the test asks for gzip, which is faster

# Depends. The shared libraries the program and the module load (libtbb12, libmetis5, libstdc++6, ...) are found by
# dpkg-shlibdeps (dpkg-dev, part of build-essential), with the versions the build was linked against.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The rest by hand:
# - the -dev packages of the CMake package's dependencies: find_package(pbd) looks for Eigen3, TBB, nlohmann_json
#   and METIS (cmake/pbdConfig.cmake.in), and the libraries are static, so a host links TBB and METIS itself. A
#   package that ships headers and a CMake package which fails without them depends on them, as Debian's -dev
#   packages depend on the -dev packages their headers need.
# - python3-numpy: the module's arrays are numpy arrays; python3-matplotlib: the plot script of `pbd study --plots`
#   (a study is the program's main job and its plots are what it is read from).
# - python3 within the minor version the module was built for: the module's file name carries that ABI (cpython-311).
set(pbd_depends "libeigen3-dev, libtbb-dev, libmetis-dev, nlohmann-json3-dev, python3-numpy, python3-matplotlib")
if(TARGET pbd_python)
  math(EXPR pbd_next_minor "${Python3_VERSION_MINOR} + 1")
  string(PREPEND pbd_depends "python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}~), "
                             "python3 (<< ${Python3_VERSION_MAJOR}.${pbd_next_minor}), ")
else()
  string(PREPEND pbd_depends "python3, ")  # the plot script
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${pbd_depends}")
# tetgen is a program pbd::tetrahedralize runs to fill a closed OBJ with tets (io/src/tetrahedralize.cpp). Only the
# scenes that fill a surface need it (built-in: balls-tets, pig-tets, squeeze, so the full study too); apt installs
# Recommends by default, and without it such a scene fails with "tetgen is not installed".
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS tetgen)
include(CPack)
