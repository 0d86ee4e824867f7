# Installs headers, libraries, the pbd program with the built-in scenes and the plot script, and a relocatable CMake
# package (find_package(pbd) → pbd::engine, pbd::io, pbd::graph_coloring, with Eigen3, TBB and METIS found for the
# consumer).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set_target_properties(pbd_engine PROPERTIES EXPORT_NAME engine)
set_target_properties(pbd_graph_coloring PROPERTIES EXPORT_NAME graph_coloring)
set_target_properties(pbd_io PROPERTIES EXPORT_NAME io)
install(TARGETS pbd_engine pbd_io pbd_graph_coloring EXPORT pbdTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine/include/ ${PROJECT_SOURCE_DIR}/io/include/
                  ${PROJECT_SOURCE_DIR}/graph_coloring/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/generated/include/pbd/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pbd)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/pbd/scenes)
# The pbd program finds its scenes and the study's plot script in share/pbd beside its own folder (cli/data_dir.hpp),
# so the installed tree works wherever it is moved.
if(TARGET pbd)
  install(TARGETS pbd RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(FILES ${PROJECT_SOURCE_DIR}/scripts/plot_study.py DESTINATION ${CMAKE_INSTALL_DATADIR}/pbd)
endif()
# The Python module's type stubs beside the module (python/CMakeLists.txt installs the module): type checkers and
# IDEs read pbd.pyi from the folder that holds pbd.cpython-*.so. The module finds the scenes in share/pbd too: from
# <prefix>/lib/python3/dist-packages, three folders up.
if(TARGET pbd_python)
  install(FILES ${PROJECT_SOURCE_DIR}/python/pbd.pyi DESTINATION ${PBD_PYTHON_INSTALL_DIR})
endif()
# The licence, under the name Debian's policy gives it (/usr/share/doc/pbd/copyright in the package).
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/pbd)
install(EXPORT pbdTargets NAMESPACE pbd:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pbdConfig.cmake.in
  ${PROJECT_BINARY_DIR}/pbdConfig.cmake INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pbdConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pbdConfig.cmake ${PROJECT_BINARY_DIR}/pbdConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindMETIS.cmake
  DESTINATION ${config_dir})
