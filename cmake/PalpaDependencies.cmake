# SPDX-License-Identifier: AGPL-3.0-or-later
# Every dependency comes from Debian's packages (scripts/setup.sh installs them).
# A missing dependency is a configure error, never a silently reduced build.
#
# The files of PALPA_PACKAGE_DEPENDENCIES are those the library's targets need
# (public dependencies and the link-only ones of the static modules). They are
# installed with the CMake package and included again by palpaConfig.cmake, so a
# project using an installed palpa finds the same packages and gets the same
# imported targets (CHOLMOD::CHOLMOD, TetGen::TetGen, the filtered Ceres::ceres).
# They therefore find packages through palpa_find_package() and report missing
# files through palpa_require_found(): here both stop the configuration; the
# installed configuration defines them so that a missing dependency makes
# find_package(palpa) fail in the usual way (see cmake/palpaConfig.cmake.in).
macro(palpa_find_package)
  find_package(${ARGN} REQUIRED)
endmacro()

# palpa_require_found(<what> <variables...>): every variable must be set by a
# find_path/find_library of <what>.
macro(palpa_require_found what)
  foreach(_palpa_var ${ARGN})
    if(NOT ${_palpa_var})
      message(FATAL_ERROR "${what} not found: ${_palpa_var} is not set (see scripts/setup.sh)")
    endif()
  endforeach()
endmacro()

set(PALPA_PACKAGE_DEPENDENCIES Eigen CHOLMOD TBB Json Fmt Spdlog Ceres CGAL TetGen ZLIB MPI)
foreach(_palpa_dep IN LISTS PALPA_PACKAGE_DEPENDENCIES)
  include(deps/${_palpa_dep})
endforeach()
include(deps/CLI11)
if(PALPA_BUILD_TESTS)
  include(deps/GTest)
endif()
if(PALPA_BUILD_BENCH)
  include(deps/Benchmark)
endif()
