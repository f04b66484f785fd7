// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/log.hpp"

namespace palpa {

namespace {
// Progress is a courtesy: a stderr that cannot be written (a full disk, a
// file-size limit, a closed pipe) must not end the run.
void put(std::FILE* f, const std::string& text) noexcept { std::fputs(text.c_str(), f); }
}  // namespace

namespace {
constexpr auto kBarRedraw = std::chrono::milliseconds(100);
constexpr auto kPlainMinGap = std::chrono::seconds(5);
constexpr int kBarWidth = 30;

std::string format_seconds(double s) {
  if (s < 60.0) return fmt::format("{:.0f}s", s);
  if (s < 3600.0) return fmt::format("{:.0f}m{:02.0f}s", std::floor(s / 60.0), std::fmod(s, 60.0));
  return fmt::format("{:.0f}h{:02.0f}m", std::floor(s / 3600.0), std::fmod(s / 60.0, 60.0));
}
}  // namespace

Progress::Progress(std::string label, std::size_t total, Style style, std::FILE* out)
    : label_(std::move(label)), total_(std::max<std::size_t>(total, 1)), style_(style), out_(out) {
  if (style_ == Style::Auto) {
    if (!info_enabled()) {
      style_ = Style::Silent;
    } else {
      style_ = isatty(fileno(out_)) != 0 ? Style::Bar : Style::Plain;
    }
  }
  start_ = std::chrono::steady_clock::now();
  last_draw_ = start_ - kPlainMinGap;
  if (style_ == Style::Plain) {
    put(out_, fmt::format("{}: started ({} steps)\n", label_, total_));
    std::fflush(out_);
  }
}

Progress::~Progress() {
  // A loop left by an exception should not claim completion: close the bar only.
  if (!finished_ && style_ == Style::Bar) {
    put(out_, "\n");
    std::fflush(out_);
  }
}

void Progress::advance(std::size_t n) {
  done_.fetch_add(n);
  if (style_ == Style::Silent) return;
  draw(false);
}

void Progress::set_note(std::string note) {
  std::lock_guard lock(mutex_);
  note_ = std::move(note);
}

void Progress::finish() {
  if (finished_) return;
  done_.store(std::max(done_.load(), total_));
  if (style_ != Style::Silent) draw(true);
  finished_ = true;
}

void Progress::draw(bool final_line) {
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  const std::size_t done = std::min(done_.load(), total_);
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string note = note_.empty() ? std::string() : "  " + note_;

  if (style_ == Style::Bar) {
    if (!final_line && now - last_draw_ < kBarRedraw) return;
    last_draw_ = now;
    const int filled = static_cast<int>(fraction * kBarWidth);
    std::string eta;
    if (!final_line && done > 0) {
      eta = " eta " + format_seconds(elapsed * (1.0 - fraction) / fraction);
    }
    put(out_, fmt::format("\r\033[2K{} [{}{}] {:3.0f}% ({}/{}) {}{}{}", label_,
               std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(kBarWidth - filled), ' '), 100.0 * fraction,
               done, total_, format_seconds(elapsed), eta, note));
    if (final_line) put(out_, "\n");
    std::fflush(out_);
    return;
  }
  // Plain: one line per new tenth, at most every few seconds, and the last one.
  const int decile = static_cast<int>(fraction * 10.0);
  if (!final_line && (decile <= last_decile_ || now - last_draw_ < kPlainMinGap)) return;
  last_decile_ = decile;
  last_draw_ = now;
  put(out_, fmt::format("{}: {:.0f}% ({}/{}) after {}{}\n", label_, 100.0 * fraction, done, total_,
             format_seconds(elapsed), note));
  std::fflush(out_);
}

}  // namespace palpa
