# SPDX-License-Identifier: AGPL-3.0-or-later
# The CMake package of an installed palpa, in <libdir>/cmake/palpa:
#   palpaConfig.cmake         finds the dependencies, then includes the targets
#   palpaConfigVersion.cmake  compatible within one major version
#   palpaTargets*.cmake       palpa::palpa and the modules palpa::palpa_<module>
#   deps/                     the dependency files of cmake/deps shared with this
#                             build (see PalpaDependencies.cmake)
include(CMakePackageConfigHelpers)

set(PALPA_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/palpa"
  CACHE STRING "Where the CMake package of palpa is installed, relative to the prefix")
mark_as_advanced(PALPA_INSTALL_CMAKEDIR)

install(EXPORT palpaTargets
  NAMESPACE palpa::
  FILE palpaTargets.cmake
  DESTINATION ${PALPA_INSTALL_CMAKEDIR})

configure_package_config_file(
  ${CMAKE_CURRENT_LIST_DIR}/palpaConfig.cmake.in
  ${PROJECT_BINARY_DIR}/package/palpaConfig.cmake
  INSTALL_DESTINATION ${PALPA_INSTALL_CMAKEDIR}
  NO_SET_AND_CHECK_MACRO
  NO_CHECK_REQUIRED_COMPONENTS_MACRO)
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/package/palpaConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMajorVersion)

set(_palpa_dep_files)
foreach(_palpa_dep IN LISTS PALPA_PACKAGE_DEPENDENCIES)
  list(APPEND _palpa_dep_files ${CMAKE_CURRENT_LIST_DIR}/deps/${_palpa_dep}.cmake)
endforeach()
install(FILES
  ${PROJECT_BINARY_DIR}/package/palpaConfig.cmake
  ${PROJECT_BINARY_DIR}/package/palpaConfigVersion.cmake
  DESTINATION ${PALPA_INSTALL_CMAKEDIR})
install(FILES ${_palpa_dep_files} DESTINATION ${PALPA_INSTALL_CMAKEDIR}/deps)
unset(_palpa_dep_files)
