# Fortran templates: a module whose procedures differ only by type, kind or rank (per-type
# specifics of a generic interface) is written once as modules/<folder>/<name>.fypp and expanded
# by fypp (https://fypp.readthedocs.io, `pip install fypp`; scripts/setup.sh installs it into
# .venv) into <build>/generated/fypp/<name>.f90 before mpmice_lib compiles, and again whenever
# the template changes (docs/architecture.md "Fortran templates").
find_program(MPMICE_FYPP fypp HINTS ${CMAKE_SOURCE_DIR}/.venv/bin)
if(NOT MPMICE_FYPP)
  message(FATAL_ERROR "fypp not found: run scripts/setup.sh (it installs fypp into .venv) or "
                      "pip install fypp")
endif()
file(GLOB_RECURSE MPMICE_FYPP_TEMPLATES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/modules/*.fypp)
set(MPMICE_FYPP_DIR ${CMAKE_BINARY_DIR}/generated/fypp)
set(MPMICE_FYPP_OUTPUTS "")
foreach(template ${MPMICE_FYPP_TEMPLATES})
  get_filename_component(name ${template} NAME_WE)
  set(output ${MPMICE_FYPP_DIR}/${name}.f90)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${MPMICE_FYPP_DIR}
    COMMAND ${MPMICE_FYPP} --line-length=132 ${template} ${output}
    DEPENDS ${template}
    COMMENT "Expanding the Fortran template ${name}.fypp"
    VERBATIM)
  list(APPEND MPMICE_FYPP_OUTPUTS ${output})
endforeach()
target_sources(mpmice_lib PRIVATE ${MPMICE_FYPP_OUTPUTS})
