// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Internal helpers shared by palpa's text readers (CSV, OBJ, OFF, PLY headers,
// TetGen, Gmsh): whole-file input with clear errors, a line cursor that knows its
// line number, and strict number parsing whose errors name the file and line.
// Not part of the public API.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"

namespace palpa::io_detail {

// Names of the coordinates, for messages about a point's x, y or z.
inline constexpr const char* kAxisNames[3] = {"x", "y", "z"};

// The whole file as bytes. Throws palpa::Error (Input) naming the file if it does
// not exist, is a folder or cannot be read. With `allow_empty` false, an empty
// file (0 bytes, or only white space for text formats: see require_content) is an
// error too. `use`: see read_input_file.
std::string read_file_bytes(const std::filesystem::path& path, bool allow_empty = false,
                            InputUse use = InputUse::Input);

// Throws "file is empty" if `text` holds nothing but white space.
void require_content(std::string_view text, const std::string& file);

// A UTF-8 byte-order mark, which editors on Windows put before a text: every
// text reader skips one at the start (it is never part of the first token).
inline constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
inline std::size_t bom_length(std::string_view text) noexcept {
  return text.starts_with(kUtf8Bom) ? kUtf8Bom.size() : 0;
}

// Walks the lines of a text, 1-based line numbers; CR before LF is dropped; a
// leading byte-order mark is skipped (offsets still count from the text's
// first byte).
class LineCursor {
 public:
  LineCursor(std::string_view text, std::string file);

  // The next line (without its end-of-line characters); false at the end.
  bool next(std::string_view& line);
  // The next line that is neither blank nor (after leading spaces) starts with
  // `comment` (pass '\0' for no comment character). Trailing comments are not
  // removed here.
  bool next_content(std::string_view& line, char comment = '#');

  std::size_t line_number() const noexcept { return line_; }
  const std::string& file() const noexcept { return file_; }
  // Byte offset just after the last line returned (start of the next line).
  std::size_t offset() const noexcept { return pos_; }
  // Moves on to byte `offset` (>= offset(), e.g. past binary data read by
  // other means); line numbers count the line ends passed over.
  void skip_to(std::size_t offset);

  ErrorContext here() const;
  [[noreturn]] void fail(const std::string& problem, const std::string& expected = {}) const;
  [[noreturn]] void fail_field(const std::string& field, const std::string& problem,
                               const std::string& expected = {}) const;

 private:
  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

// A finite number from `token`, or an Input error at the cursor's line naming
// `what` ("vertex 3 coordinate y") and telling a non-number from NaN/Inf.
double parse_number(std::string_view token, const LineCursor& at, const std::string& what);
// An integer from `token`, or an Input error as above.
long long parse_int(std::string_view token, const LineCursor& at, const std::string& what);

// The same checks without a cursor, for callers that build their own context.
// Returns the problem text ("'abc' is not a number") or an empty string.
std::string number_problem(std::string_view token);

// Splits a line into white-space separated tokens, dropping a trailing comment
// that starts with `comment` ('\0' for none).
std::vector<std::string_view> tokens_of(std::string_view line, char comment = '#');

}  // namespace palpa::io_detail
