# SPDX-License-Identifier: AGPL-3.0-or-later
# Warnings for palpa's own code, as an interface target. Third-party headers come
# in through imported targets and are treated as system headers, so they do not
# trip these flags.
add_library(palpa_warnings INTERFACE)
target_compile_options(palpa_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wimplicit-fallthrough)
if(PALPA_WERROR)
  target_compile_options(palpa_warnings INTERFACE -Werror)
endif()
