# SPDX-License-Identifier: AGPL-3.0-or-later
# TetGen 1.5 (Debian's libtet1.5-dev ships no CMake package): locate it by hand
# and wrap it in an imported target. The library is built with TETLIBRARY, so
# its errors are thrown as int; consumers must define it too. Only
# src/palpa/mesh/tetgen_mesher.cpp includes it.
find_path(TETGEN_INCLUDE_DIR tetgen.h)
find_library(TETGEN_LIBRARY tet)
palpa_require_found(TetGen TETGEN_INCLUDE_DIR TETGEN_LIBRARY)
if(NOT TARGET palpa_tetgen)
  add_library(palpa_tetgen INTERFACE IMPORTED)
  set_target_properties(palpa_tetgen PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${TETGEN_INCLUDE_DIR}"
    INTERFACE_COMPILE_DEFINITIONS TETLIBRARY
    INTERFACE_LINK_LIBRARIES "${TETGEN_LIBRARY}")
endif()
if(NOT TARGET TetGen::TetGen)
  add_library(TetGen::TetGen ALIAS palpa_tetgen)
endif()
