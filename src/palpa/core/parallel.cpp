// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <atomic>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {

bool is_interrupt(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const Error& x) {
    return x.kind() == ErrorKind::Interrupted;
  } catch (...) {
    return false;
  }
}

}  // namespace

void rethrow_first(const std::vector<std::exception_ptr>& errors) {
  std::exception_ptr first;
  for (const std::exception_ptr& e : errors) {
    if (!e) continue;
    if (is_interrupt(e)) std::rethrow_exception(e);
    if (!first) first = e;
  }
  if (first) std::rethrow_exception(first);
}

void parallel_for_each_index(std::size_t n, const std::function<void(std::size_t)>& body) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<bool> failed{false};
  tbb::task_group_context isolated(tbb::task_group_context::isolated);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 1),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          if (failed.load(std::memory_order_relaxed)) return;
          try {
            body(i);
          } catch (...) {
            errors[i] = std::current_exception();
            failed = true;
          }
        }
      },
      tbb::simple_partitioner(), isolated);
  rethrow_first(errors);
}

}  // namespace palpa
