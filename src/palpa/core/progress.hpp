// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Progress reporting for long loops (Newton steps over depths, fits, shape
// optimization). On a terminal it draws one bar that redraws in place; otherwise
// (CI, a log file) it prints a few plain lines: one per tenth of the work, at most
// every few seconds, and one at the end. Silent under --quiet.
// advance() is thread-safe, so a TBB loop may report from its workers.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <mutex>
#include <string>

namespace palpa {

class Progress {
 public:
  enum class Style { Auto, Bar, Plain, Silent };

  // label: what is being done ("poke depths"); total: units of work (> 0).
  Progress(std::string label, std::size_t total, Style style = Style::Auto,
           std::FILE* out = stderr);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::size_t n = 1);
  // Free text shown after the counter ("residual 3e-9"), e.g. the latest figure.
  void set_note(std::string note);
  // Marks the work complete and prints the closing line (also done by the destructor).
  void finish();

  std::size_t done() const noexcept { return done_.load(); }
  std::size_t total() const noexcept { return total_; }

 private:
  void draw(bool final_line);

  std::string label_;
  std::size_t total_;
  Style style_;
  std::FILE* out_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
  std::string note_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  int last_decile_ = -1;
  bool finished_ = false;
};

}  // namespace palpa
