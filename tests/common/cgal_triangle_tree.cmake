# SPDX-License-Identifier: AGPL-3.0-or-later
# palpa_test_cgal: CGAL's AABB tree as the reference closest-point engine of
# the tests and the contact benchmark (common/cgal_triangle_tree.hpp), not
# part of the library. Included by tests/ and by bench/ (which may be
# configured without the tests); whichever comes first defines it. Out of
# `all`: built only for the programs that link it. Its one translation unit
# is kept whole (CGAL's compile options stay in it) and, like the library's
# CGAL wrappers, keeps AddressSanitizer but not UBSan.
if(NOT TARGET palpa_test_cgal)
  add_library(palpa_test_cgal STATIC EXCLUDE_FROM_ALL ${CMAKE_CURRENT_LIST_DIR}/cgal_triangle_tree.cpp)
  target_include_directories(palpa_test_cgal PUBLIC ${CMAKE_CURRENT_LIST_DIR}/..)
  target_link_libraries(palpa_test_cgal
    PUBLIC Eigen3::Eigen
    PRIVATE CGAL::CGAL palpa_sanitizers palpa_warnings)
  palpa_sanitize_memory_only(${CMAKE_CURRENT_LIST_DIR}/cgal_triangle_tree.cpp)
endif()
