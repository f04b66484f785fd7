// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/detail/text_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "palpa/core/input_file.hpp"
#include "palpa/core/text.hpp"

namespace palpa::io_detail {

std::string read_file_bytes(const std::filesystem::path& path, bool allow_empty, InputUse use) {
  std::string bytes = read_input_file(path, use);
  if (!allow_empty && bytes.empty()) throw_input_error("file is empty", ErrorContext{path.string(), 0, 0, ""});
  return bytes;
}

void require_content(std::string_view text, const std::string& file) {
  if (trim(text).empty()) {
    ErrorContext ctx;
    ctx.file = file;
    throw_input_error(text.empty() ? "file is empty" : "file holds only white space", ctx);
  }
}

LineCursor::LineCursor(std::string_view text, std::string file)
    : text_(text), file_(std::move(file)), pos_(bom_length(text)) {}

bool LineCursor::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++line_;
  return true;
}

void LineCursor::skip_to(std::size_t offset) {
  const std::size_t to = std::min(offset, text_.size());
  if (to <= pos_) return;
  line_ +=
      static_cast<std::size_t>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                          text_.begin() + static_cast<std::ptrdiff_t>(to), '\n'));
  pos_ = to;
}

bool LineCursor::next_content(std::string_view& line, char comment) {
  std::string_view l;
  while (next(l)) {
    const std::string_view t = trim(l);
    if (t.empty()) continue;
    if (comment != '\0' && t.front() == comment) continue;
    line = l;
    return true;
  }
  return false;
}

ErrorContext LineCursor::here() const {
  ErrorContext ctx;
  ctx.file = file_;
  ctx.line = line_;
  return ctx;
}

void LineCursor::fail(const std::string& problem, const std::string& expected) const {
  throw_input_error(problem, here(), expected);
}

void LineCursor::fail_field(const std::string& field, const std::string& problem,
                            const std::string& expected) const {
  ErrorContext ctx = here();
  ctx.field = field;
  throw_input_error(problem, ctx, expected);
}

std::string number_problem(std::string_view token) {
  const std::string_view t = trim(token);
  if (t.empty()) return "empty value";
  if (parse_finite_double(t)) return {};
  // Tell NaN/Inf (a number, but not a usable one) from text that is no number.
  std::string_view num = t;
  if (num.front() == '+' || num.front() == '-') num.remove_prefix(1);
  double value = 0.0;
  const char* end = num.data() + num.size();
  const auto [ptr, ec] = std::from_chars(num.data(), end, value, std::chars_format::general);
  if (ptr == end && (ec == std::errc::result_out_of_range || !std::isfinite(value))) {
    return fmt::format("'{}' is not a finite number", t);
  }
  return fmt::format("'{}' is not a number", t);
}

double parse_number(std::string_view token, const LineCursor& at, const std::string& what) {
  if (const auto v = parse_finite_double(token)) return *v;
  at.fail_field(what, number_problem(token), "a finite number");
}

long long parse_int(std::string_view token, const LineCursor& at, const std::string& what) {
  if (const auto v = parse_integer(token)) return *v;
  at.fail_field(what, fmt::format("'{}' is not an integer", trim(token)), "an integer");
}

std::vector<std::string_view> tokens_of(std::string_view line, char comment) {
  if (comment != '\0') {
    const std::size_t c = line.find(comment);
    if (c != std::string_view::npos) line = line.substr(0, c);
  }
  return split_whitespace(line);
}

}  // namespace palpa::io_detail
