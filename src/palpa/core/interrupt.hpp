// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Cooperative interruption. The command line installs handlers for SIGINT and
// SIGTERM; long loops call check_interrupt() between units of work, which throws
// palpa::Error (kind Interrupted) so that destructors run: temporary output files
// are removed and checkpoints already written stay valid for --resume.

#include <cstddef>
#include <functional>
#include <string>

namespace palpa {

// Installs the SIGINT/SIGTERM handlers (idempotent). A second Ctrl-C while the
// first is being honoured restores the default action, so it kills at once (a
// repeated SIGTERM is ignored, and so is a SIGINT within 0.2 s of the first:
// one signal sent to the process and to its group).
// A watchdog thread makes sure a signal is honoured within a second, even
// inside a library call that never reaches a check_interrupt() (a CGAL
// remeshing, one large factorization): kInterruptGraceSeconds after the
// signal it removes the temporary files of outputs being written and ends
// the process with interrupt_exit_code(). Checkpoints and finished files stay.
// SIGXFSZ is ignored: past a file-size limit a write fails as on a full disk.
void install_interrupt_handlers();
inline constexpr double kInterruptGraceSeconds = 0.8;

// The exit code of an interrupted run: 128 + the signal (130 for SIGINT, 143
// for SIGTERM); 130 when the interrupt was requested by a test.
int interrupt_exit_code() noexcept;

// The temporaries the watchdog removes (AtomicFile registers its own).
void register_temporary(const std::string& path);
void unregister_temporary(const std::string& path);

// Tidying the watchdog does after removing the temporaries, just before it
// ends the process (OutputFolder removes the folders a failed run created):
// `tidy` must be quick and not throw; it runs on the watchdog's thread while
// the registry is locked, so unregistering waits for it. Returns the handle
// to unregister with.
std::size_t register_forced_exit_tidy(std::function<void()> tidy);
void unregister_forced_exit_tidy(std::size_t handle);

// True once an interrupt was requested.
bool interrupt_requested() noexcept;

// Throws palpa::Error(ErrorKind::Interrupted) if an interrupt was requested.
void check_interrupt();

// For tests: request or clear an interrupt as if a signal had arrived.
void request_interrupt() noexcept;
void clear_interrupt() noexcept;
// For tests: request an interrupt at the n-th check_interrupt() from now (on
// whichever thread makes it), n ≥ 1; clear_interrupt() disarms it.
void request_interrupt_at_check(long n) noexcept;

}  // namespace palpa
