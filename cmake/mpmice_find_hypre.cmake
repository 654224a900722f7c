# Find hypre (header HYPRE_struct_ls.h, library HYPRE) and define the imported target
# hypre::hypre; sets MPMICE_HYPRE_FOUND. Used by the top-level CMakeLists.txt and, installed next to
# it, by mpmiceConfig.cmake, so a code linking the installed library finds hypre the same way.
# Hints: CMAKE_PREFIX_PATH, HYPRE_ROOT, or the cache variables HYPRE_INCLUDE_DIR / HYPRE_LIBRARY.
set(MPMICE_HYPRE_FOUND FALSE)
if(TARGET hypre::hypre)
  set(MPMICE_HYPRE_FOUND TRUE)
  return()
endif()
# (HYPRE_ROOT is looked at explicitly: CMake applies <Package>_ROOT inside find_package only)
find_path(HYPRE_INCLUDE_DIR HYPRE_struct_ls.h HINTS ${HYPRE_ROOT} $ENV{HYPRE_ROOT}
  PATH_SUFFIXES hypre include include/hypre)
find_library(HYPRE_LIBRARY NAMES HYPRE HINTS ${HYPRE_ROOT} $ENV{HYPRE_ROOT} PATH_SUFFIXES lib lib64)
if(HYPRE_INCLUDE_DIR AND HYPRE_LIBRARY)
  add_library(hypre::hypre UNKNOWN IMPORTED)
  set_target_properties(hypre::hypre PROPERTIES IMPORTED_LOCATION "${HYPRE_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}")
  set(MPMICE_HYPRE_FOUND TRUE)
endif()
