// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Logging with levels. The command line maps --quiet / (default) / --verbose /
// -vv to Warn / Info / Debug / Trace. Messages go to stderr so that stdout stays
// free for data a user may pipe. Library code logs through these functions (or
// spdlog directly) and never prints with printf.

#include <spdlog/spdlog.h>

namespace palpa {

enum class Verbosity { Quiet, Normal, Verbose, Trace };

// Installs palpa's stderr logger ("palpa: message", with the level named for
// warnings and errors) and sets its level. Safe to call more than once.
void configure_logging(Verbosity verbosity);

// True when informational output (progress bars, per-step lines) should be shown.
bool info_enabled() noexcept;

}  // namespace palpa
