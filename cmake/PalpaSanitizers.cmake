# SPDX-License-Identifier: AGPL-3.0-or-later
# AddressSanitizer + UndefinedBehaviorSanitizer for every palpa target.
# UBSan is made fatal so a report fails the test that triggered it.
add_library(palpa_sanitizers INTERFACE)
if(PALPA_SANITIZE)
  set(_palpa_san_flags -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_compile_options(palpa_sanitizers INTERFACE ${_palpa_san_flags})
  target_link_options(palpa_sanitizers INTERFACE ${_palpa_san_flags})
endif()

# palpa_sanitize_memory_only(<source>...): the thin translation units that
# wrap CGAL keep AddressSanitizer but not UBSan. UBSan's checks on CGAL's
# templates (exact predicates, kernels, AABB trees) nearly double the compile
# time of these few files (cgal_offset.cpp: 88 s with ASan alone, 147 s with
# both), which were a quarter of the sanitizer build, while palpa's code in
# them is a few calls into CGAL; memory errors are still caught.
# Source options come after the target's, so this turns UBSan off for these
# files only, after the options already set on them.
function(palpa_sanitize_memory_only)
  if(NOT PALPA_SANITIZE)
    return()
  endif()
  foreach(_src IN LISTS ARGN)
    get_source_file_property(_opts ${_src} COMPILE_OPTIONS)
    if(NOT _opts)
      set(_opts "")
    endif()
    list(APPEND _opts -fno-sanitize=undefined)
    set_source_files_properties(${_src} PROPERTIES COMPILE_OPTIONS "${_opts}")
  endforeach()
endfunction()
