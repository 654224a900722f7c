# Install rules and the exported CMake package (docs/install.md). Layout under the prefix:
#   bin/mpmice, bin/mc_element        the programs
#   lib/libmpmice.a                   the library, imported target mpmice::mpmice
#   include/mpmice/*.mod              its Fortran module files (same compiler needed to use them)
#   lib/cmake/mpmice/                 mpmiceConfig.cmake, mpmiceConfigVersion.cmake, targets
#   share/mpmice/postproc/            the postprocessing package (PYTHONPATH=<prefix>/share/mpmice)
#   share/mpmice/namelists/           the example cases
#   share/doc/mpmice/                 README.md and docs/
# (lib may be lib64 and the others differ where GNUInstallDirs says so.) postproc sits next to
# namelists/ as in the source tree, so its scene scripts (python -m postproc.<x>) find their
# namelists the same way in both.
include(CMakePackageConfigHelpers)
set(MPMICE_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mpmice)

install(TARGETS mpmice mc_element RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS mpmice_lib EXPORT mpmiceTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# every module of the library (build/mod holds those of mpmice_lib only)
install(DIRECTORY ${CMAKE_BINARY_DIR}/mod/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mpmice
  FILES_MATCHING PATTERN "*.mod" PATTERN "*.smod")

# mpmiceTargets.cmake defines mpmice::mpmice; mpmiceConfig.cmake finds the dependencies first.
install(EXPORT mpmiceTargets NAMESPACE mpmice:: DESTINATION ${MPMICE_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/mpmiceConfig.cmake.in
  ${CMAKE_BINARY_DIR}/cmake/mpmiceConfig.cmake INSTALL_DESTINATION ${MPMICE_INSTALL_CMAKEDIR})
# 0.x: a different minor version may change the modules, so only x.y.* counts as compatible
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/mpmiceConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/cmake/mpmiceConfig.cmake
  ${CMAKE_BINARY_DIR}/cmake/mpmiceConfigVersion.cmake
  ${CMAKE_SOURCE_DIR}/cmake/mpmice_find_hypre.cmake DESTINATION ${MPMICE_INSTALL_CMAKEDIR})

# Python postprocessing (optional: Spack's ~postproc), example cases, user documentation
option(MPMICE_INSTALL_POSTPROC "Install the Python postprocessing package postproc" ON)
if(MPMICE_INSTALL_POSTPROC)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/postproc/
    DESTINATION ${CMAKE_INSTALL_DATADIR}/mpmice/postproc
    FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
endif()
install(DIRECTORY ${CMAKE_SOURCE_DIR}/namelists/
  DESTINATION ${CMAKE_INSTALL_DATADIR}/mpmice/namelists)
install(FILES ${CMAKE_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
