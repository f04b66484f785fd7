// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A small scanner for the XML palpa reads (VTK .vtu headers and .pvd files):
// start, end and empty-element tags with their attributes, and the text between
// tags. Comments, processing instructions and DOCTYPE are skipped; entities
// &lt; &gt; &amp; &quot; &apos; are decoded in attribute values. Not a general
// XML parser; not part of the public API.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace palpa::io_detail {

struct XmlTag {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  bool closing = false;       // </name>
  bool self_closing = false;  // <name ... />
  std::size_t begin = 0;      // offset of '<'

  const std::string* attribute(std::string_view key) const noexcept;
};

class XmlScanner {
 public:
  XmlScanner(std::string_view text, std::string file);

  // The next tag; `text_before` is the raw text between the previous tag and
  // this one. False at the end of the text (the trailing text is then in
  // `text_before`). Malformed markup: palpa::Error (Input) naming the line.
  bool next(XmlTag& tag, std::string_view& text_before);

  // 1-based line of byte `offset`.
  std::size_t line_of(std::size_t offset) const noexcept;
  const std::string& file() const noexcept { return file_; }

 private:
  [[noreturn]] void fail(std::size_t offset, const std::string& problem) const;

  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  // line_of() cache: lines up to counted_offset_.
  mutable std::size_t counted_offset_ = 0;
  mutable std::size_t counted_lines_ = 1;
};

// Escapes & < > " for an attribute value.
std::string xml_escape(std::string_view s);

}  // namespace palpa::io_detail
