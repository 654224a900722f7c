# The namelist variables are declared once, in modules/config/namelist/*.toml; the Fortran
# include files that hold their type components, reads, table, echo and range checks are
# generated from that list into <build>/generated/config by scripts/generate_namelists.py
# (Python >= 3.11, standard library only) before mpmice_lib compiles, and again whenever the
# list or the generator changes; a file whose text stays the same is not rewritten, so only the
# sources that include a changed file recompile (docs/architecture.md "Adding a namelist
# variable").
find_package(Python3 3.11 REQUIRED COMPONENTS Interpreter)
file(GLOB MPMICE_NAMELIST_LIST CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/modules/config/namelist/*.toml)
set(MPMICE_NAMELIST_DIR ${CMAKE_BINARY_DIR}/generated/config)
add_custom_command(
  OUTPUT ${MPMICE_NAMELIST_DIR}/config_nml.stamp
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_SOURCE_DIR}/scripts/generate_namelists.py
          --list ${CMAKE_SOURCE_DIR}/modules/config/namelist --fortran ${MPMICE_NAMELIST_DIR}
  COMMAND ${CMAKE_COMMAND} -E touch ${MPMICE_NAMELIST_DIR}/config_nml.stamp
  DEPENDS ${CMAKE_SOURCE_DIR}/scripts/generate_namelists.py ${MPMICE_NAMELIST_LIST}
  COMMENT "Generating the namelist code from modules/config/namelist"
  VERBATIM)
add_custom_target(mpmice_namelists DEPENDS ${MPMICE_NAMELIST_DIR}/config_nml.stamp)
add_dependencies(mpmice_lib mpmice_namelists)
target_include_directories(mpmice_lib PRIVATE ${MPMICE_NAMELIST_DIR})
