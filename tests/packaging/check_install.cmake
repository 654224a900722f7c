# ctest packaging.install_consumer (tests/packaging/CMakeLists.txt), run as `cmake -P`:
#  1. `cmake --install` the build tree into a fresh prefix under WORK_DIR and check the layout
#     (docs/install.md), the link dependencies of mpmice::mpmice and the version file's rule;
#  2. configure and build tests/packaging/consumer against it with find_package(mpmice);
#  3. run the installed `mpmice --version`, a two-step run of the installed example
#     heat_conduction_1d.nml, and the consumer on the first dump;
#  4. require one version everywhere: project(VERSION) (EXPECTED_VERSION), the installed
#     mpmiceConfigVersion.cmake, the version find_package reported, the Fortran constant the
#     consumer was compiled against, `mpmice --version`, the run's log line `mpmice: version` and
#     the dump attribute `mpmice_version`.
# Any failure ends the script with FATAL_ERROR (non-zero exit status).
foreach(var IN ITEMS BUILD_DIR SOURCE_DIR WORK_DIR EXPECTED_VERSION GENERATOR Fortran_COMPILER
                     C_COMPILER MPIEXEC NUMPROC_FLAG BINDIR LIBDIR INCLUDEDIR DATADIR DOCDIR
                     POSTPROC)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_install.cmake: -D${var}=... missing")
  endif()
endforeach()

# run_checked(<output var> COMMAND ...): run, fail with the output unless the status is 0
function(run_checked out_var)
  execute_process(${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (status ${status}): ${cmd}\n${out}\n${err}")
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# 1. install and layout
run_checked(out COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file IN ITEMS
    ${BINDIR}/mpmice ${BINDIR}/mc_element
    ${LIBDIR}/libmpmice.a
    ${INCLUDEDIR}/mpmice/mpmice_build_info.mod ${INCLUDEDIR}/mpmice/io_hdf5.mod
    ${INCLUDEDIR}/mpmice/config_cli.mod
    ${LIBDIR}/cmake/mpmice/mpmiceConfig.cmake ${LIBDIR}/cmake/mpmice/mpmiceConfigVersion.cmake
    ${LIBDIR}/cmake/mpmice/mpmiceTargets.cmake ${LIBDIR}/cmake/mpmice/mpmice_find_hypre.cmake
    ${DATADIR}/mpmice/namelists/heat_conduction_1d.nml
    ${DOCDIR}/README.md ${DOCDIR}/docs/install.md)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: <prefix>/${file}")
  endif()
endforeach()
set(postproc_files ${DATADIR}/mpmice/postproc/__init__.py
  ${DATADIR}/mpmice/postproc/run_case.py)
foreach(file IN LISTS postproc_files)
  if(POSTPROC AND NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: <prefix>/${file}")
  elseif(NOT POSTPROC AND EXISTS ${prefix}/${file})
    message(FATAL_ERROR "installed although MPMICE_INSTALL_POSTPROC is OFF: <prefix>/${file}")
  endif()
endforeach()
file(STRINGS ${prefix}/${LIBDIR}/cmake/mpmice/mpmiceTargets.cmake link_line
  REGEX "INTERFACE_LINK_LIBRARIES")
foreach(dep IN ITEMS MPI::MPI_Fortran HDF5::HDF5 hypre::hypre LAPACK::LAPACK)
  if(NOT link_line MATCHES "${dep}")
    message(FATAL_ERROR "mpmice::mpmice does not carry the link dependency ${dep}: ${link_line}")
  endif()
endforeach()

# the version the package file states, and its compatibility rule (same major.minor):
# version_compatible(<requested x.y.z> <result var>) as find_package(mpmice x.y.z) would decide
function(version_compatible requested out_var)
  set(PACKAGE_FIND_VERSION ${requested})
  string(REPLACE "." ";" parts ${requested})
  list(GET parts 0 PACKAGE_FIND_VERSION_MAJOR)
  list(GET parts 1 PACKAGE_FIND_VERSION_MINOR)
  include(${prefix}/${LIBDIR}/cmake/mpmice/mpmiceConfigVersion.cmake)
  set(${out_var} "${PACKAGE_VERSION_COMPATIBLE}" PARENT_SCOPE)
  set(package_version "${PACKAGE_VERSION}" PARENT_SCOPE)
endfunction()
version_compatible(${EXPECTED_VERSION} same)
string(REPLACE "." ";" parts ${EXPECTED_VERSION})
list(GET parts 0 major)
list(GET parts 1 minor)
math(EXPR next_minor "${minor} + 1")
version_compatible(${major}.${next_minor}.0 newer)
if(NOT same OR newer)
  message(FATAL_ERROR "mpmiceConfigVersion.cmake: ${EXPECTED_VERSION} compatible: '${same}' "
    "(must be TRUE), ${major}.${next_minor}.0 compatible: '${newer}' (must be FALSE)")
endif()

# 2. the consumer, through find_package(mpmice)
set(consumer_build ${WORK_DIR}/consumer)
run_checked(out COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/packaging/consumer
  -B ${consumer_build} -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_PREFIX_PATH=${prefix} -DMPMICE_REQUEST=${EXPECTED_VERSION}
  -DCMAKE_Fortran_COMPILER=${Fortran_COMPILER}
  -DCMAKE_C_COMPILER=${C_COMPILER})
run_checked(out COMMAND ${CMAKE_COMMAND} --build ${consumer_build})
file(READ ${consumer_build}/found_version.txt found_version)

# 3. the installed program, a run of an installed example, the consumer on its dump
run_checked(out COMMAND ${MPIEXEC} ${NUMPROC_FLAG} 1 ${prefix}/${BINDIR}/mpmice --version)
string(STRIP "${out}" out)
if(NOT out MATCHES "^mpmice ([^ \n]+)$")
  message(FATAL_ERROR "mpmice --version printed '${out}', not 'mpmice <version>'")
endif()
set(program_version ${CMAKE_MATCH_1})

set(run_dir ${WORK_DIR}/run)
run_checked(out COMMAND ${MPIEXEC} ${NUMPROC_FLAG} 1 ${prefix}/${BINDIR}/mpmice
  ${prefix}/${DATADIR}/mpmice/namelists/heat_conduction_1d.nml
  --set "&run output_dir = '${run_dir}', end_time = 2.0e-3, output_interval = 1.0e-3 /"
  WORKING_DIRECTORY ${WORK_DIR})
file(GLOB dumps ${run_dir}/heat1d_*.h5)
list(SORT dumps)
if(NOT dumps)
  message(FATAL_ERROR "the installed mpmice wrote no dump in ${run_dir}:\n${out}")
endif()
list(GET dumps 0 dump)
file(STRINGS ${run_dir}/heat1d.log log_line REGEX "^mpmice: version ")
string(REPLACE "mpmice: version " "" log_version "${log_line}")

run_checked(out COMMAND ${MPIEXEC} ${NUMPROC_FLAG} 1 ${consumer_build}/mpmice_consumer ${dump})
if(NOT out MATCHES "library_version ([^ \n]+)\n")
  message(FATAL_ERROR "consumer printed no library_version line:\n${out}")
endif()
set(library_version ${CMAKE_MATCH_1})
if(NOT out MATCHES "dump_version ([^ \n]+)")
  message(FATAL_ERROR "consumer printed no dump_version line:\n${out}")
endif()
set(dump_version ${CMAKE_MATCH_1})

# 4. one version everywhere
foreach(source IN ITEMS package_version found_version library_version program_version
                        log_version dump_version)
  message(STATUS "${source}: ${${source}}")
  if(NOT "${${source}}" STREQUAL "${EXPECTED_VERSION}")
    message(FATAL_ERROR "${source} is '${${source}}', project(VERSION) is '${EXPECTED_VERSION}'")
  endif()
endforeach()
message(STATUS "install, find_package(mpmice) and the version agree: ${EXPECTED_VERSION}")
