# CGAL 5.5 (Debian's libcgal-dev, header-only): used inside .cpp files only.
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL REQUIRED)
