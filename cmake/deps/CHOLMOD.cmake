# SPDX-License-Identifier: AGPL-3.0-or-later
# SuiteSparse 5.x in Debian ships no CMake package: locate CHOLMOD by hand and
# wrap it in an imported target. Only .cpp files of the solve module include it.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
palpa_require_found(CHOLMOD CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSECONFIG_LIBRARY)
if(NOT TARGET palpa_cholmod)
  add_library(palpa_cholmod INTERFACE IMPORTED)
  set_target_properties(palpa_cholmod PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${CHOLMOD_LIBRARY};${SUITESPARSECONFIG_LIBRARY}")
endif()
if(NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD ALIAS palpa_cholmod)
endif()
