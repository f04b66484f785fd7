#pragma once
// Cooperative interruption. The command line installs handlers for SIGINT and
// SIGTERM; long loops call check_interrupt() between units of work, which throws
// palpa::Error (kind Interrupted) so that destructors run: temporary output files
// are removed and checkpoints already written stay valid for --resume.

namespace palpa {

// Installs the SIGINT/SIGTERM handlers (idempotent). A second Ctrl-C while the
// first is being honoured restores the default action, so it kills at once.
void install_interrupt_handlers();

// True once an interrupt was requested.
bool interrupt_requested() noexcept;

// Throws palpa::Error(ErrorKind::Interrupted) if an interrupt was requested.
void check_interrupt();

// For tests: request or clear an interrupt as if a signal had arrived.
void request_interrupt() noexcept;
void clear_interrupt() noexcept;

}  // namespace palpa
