// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Parallel loops whose iterations may throw (a solver that fails, an
// interrupt).
//
// When a task of a tbb::parallel_for throws, TBB cancels its context and every
// context bound to it, i.e. the loops nested inside the other iterations, and a
// cancelled loop returns as if it had finished. An iteration that then reads
// what its nested loop should have computed reads results that never were
// (the Ctrl-C crash of the depth search). parallel_for_each_index runs each
// iteration in an isolated context and catches what it throws, so that
// nothing is cancelled behind anyone's back: iterations that have not started
// when one has failed are skipped, those running finish (they stop at their
// next check_interrupt() after an interrupt), and the loop then rethrows.

#include <cstddef>
#include <exception>
#include <functional>
#include <vector>

namespace palpa {

// The most threads palpa may be told to use (--threads, palpa.set_threads).
inline constexpr int kMaxThreads = 4096;

// Runs body(i) for every i in [0, n), in parallel, then rethrows what the
// iterations threw (rethrow_first). body(i) for one i runs on one thread.
void parallel_for_each_index(std::size_t n, const std::function<void(std::size_t)>& body);

// Rethrows one of `errors` (null entries are no error): an interrupt first
// (the user asked to stop), else the one with the lowest index. Returns when
// every entry is null.
void rethrow_first(const std::vector<std::exception_ptr>& errors);

}  // namespace palpa
