# AddressSanitizer + UndefinedBehaviorSanitizer for every palpa target.
# UBSan is made fatal so a report fails the test that triggered it.
add_library(palpa_sanitizers INTERFACE)
if(PALPA_SANITIZE)
  set(_palpa_san_flags -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_compile_options(palpa_sanitizers INTERFACE ${_palpa_san_flags})
  target_link_options(palpa_sanitizers INTERFACE ${_palpa_san_flags})
endif()
