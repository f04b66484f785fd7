# SPDX-License-Identifier: AGPL-3.0-or-later
# The test palpa_package: installs the built tree into a fresh prefix, then
# configures, builds and runs the project of this directory against it, as a
# user of the installed library would. It installs what is already built and
# builds only the consumer's one file: palpa must be built first (ctest runs
# after the build).
#   cmake -DPALPA_BUILD_DIR=<palpa's build> -DWORK_DIR=<scratch> -DCXX_COMPILER=<c++>
#         -DGENERATOR=<generator> [-DMAKE_PROGRAM=<ninja>] [-DBUILD_TYPE=<type>]
#         -P package_test.cmake
foreach(_var PALPA_BUILD_DIR WORK_DIR CXX_COMPILER GENERATOR)
  if(NOT ${_var})
    message(FATAL_ERROR "package_test.cmake: -D${_var}=... is required")
  endif()
endforeach()
set(consumer_source "${CMAKE_CURRENT_LIST_DIR}")
set(prefix "${WORK_DIR}/prefix")
set(consumer_build "${WORK_DIR}/consumer")

# run(<step> <command...>): runs the command, stops the test naming the step
# and showing the command's output if it fails.
function(run step)
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc
    OUTPUT_VARIABLE out
    ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    list(JOIN ARGN " " cmd)
    message(FATAL_ERROR "package test failed at step '${step}' (exit status ${rc}):\n  ${cmd}\n${out}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# 1. Install. A missing file means palpa is not (fully) built.
if(NOT EXISTS "${PALPA_BUILD_DIR}/cmake_install.cmake")
  message(FATAL_ERROR "package test failed at step 'install': ${PALPA_BUILD_DIR} is not a configured build of palpa")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --install "${PALPA_BUILD_DIR}" --prefix "${prefix}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "package test failed at step 'install' (exit status ${rc}): "
    "cmake --install ${PALPA_BUILD_DIR} --prefix ${prefix}\n"
    "Build palpa first (cmake --build ${PALPA_BUILD_DIR}).\n${out}")
endif()
foreach(_file
    include/palpa/core/units.hpp
    include/palpa/core/version.hpp)
  if(NOT EXISTS "${prefix}/${_file}")
    message(FATAL_ERROR "package test failed at step 'install': ${prefix}/${_file} was not installed")
  endif()
endforeach()
file(GLOB_RECURSE _config "${prefix}/*/palpaConfig.cmake")
if(NOT _config)
  message(FATAL_ERROR "package test failed at step 'install': no palpaConfig.cmake under ${prefix}")
endif()

# 2. Configure the consumer with only the prefix to find palpa by.
set(_configure ${CMAKE_COMMAND} -S "${consumer_source}" -B "${consumer_build}"
  -G "${GENERATOR}"
  "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
  "-DCMAKE_PREFIX_PATH=${prefix}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
if(MAKE_PROGRAM)
  list(APPEND _configure "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
if(BUILD_TYPE)
  list(APPEND _configure "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}")
endif()
run(configure ${_configure})
file(STRINGS "${consumer_build}/CMakeCache.txt" _palpa_dir REGEX "^palpa_DIR:")
string(REGEX REPLACE "^palpa_DIR:[A-Z]+=" "" _palpa_dir "${_palpa_dir}")
file(REAL_PATH "${prefix}" _real_prefix)
file(REAL_PATH "${_palpa_dir}" _real_palpa_dir)
string(FIND "${_real_palpa_dir}/" "${_real_prefix}/" _at)
if(NOT _at EQUAL 0)
  message(FATAL_ERROR "package test failed at step 'configure': palpa was found in ${_palpa_dir}, not in the fresh install ${prefix}")
endif()

# palpa's own warning and sanitizer flags stay out of the consumer's commands.
if(EXISTS "${consumer_build}/compile_commands.json")
  file(READ "${consumer_build}/compile_commands.json" _commands)
  foreach(_flag -Werror -Wshadow -Wold-style-cast -fsanitize)
    string(FIND "${_commands}" "${_flag}" _at)
    if(NOT _at EQUAL -1)
      message(FATAL_ERROR "package test failed at step 'configure': palpa's targets pass ${_flag} to the consumer:\n${_commands}")
    endif()
  endforeach()
endif()

# 3. Build the consumer (one file).
run(build ${CMAKE_COMMAND} --build "${consumer_build}")

# 4. Run it: it checks results of palpa's calls and exits non-zero if one is wrong.
set(_exe "${consumer_build}/palpa_consumer")
if(NOT EXISTS "${_exe}")
  message(FATAL_ERROR "package test failed at step 'build': ${_exe} was not produced")
endif()
run(run "${_exe}")
message(STATUS "${run_output}")
