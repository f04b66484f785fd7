# SPDX-License-Identifier: AGPL-3.0-or-later
# CGAL 5.5 (header-only, with GMP/MPFR), included only by the .cpp files of
# contact (detail/cgal_checks.cpp) and mesh (detail/), and by the tests' and
# benchmarks' reference tree (tests/common/cgal_triangle_tree.cpp).
# CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE: the presets choose it.
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
palpa_find_package(CGAL 5.5)
