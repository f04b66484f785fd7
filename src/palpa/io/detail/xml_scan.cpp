// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/detail/xml_scan.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "palpa/core/error.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa::io_detail {

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}
bool is_name_char(char c) {
  return c != '\0' && !is_space(c) && c != '=' && c != '>' && c != '/' && c != '<' && c != '"' &&
         c != '\'';
}

std::optional<std::string> unescape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '&') {
      out += s[i];
      continue;
    }
    const std::size_t semi = s.find(';', i);
    if (semi == std::string_view::npos) return std::nullopt;
    const std::string_view entity = s.substr(i + 1, semi - i - 1);
    if (entity == "lt") {
      out += '<';
    } else if (entity == "gt") {
      out += '>';
    } else if (entity == "amp") {
      out += '&';
    } else if (entity == "quot") {
      out += '"';
    } else if (entity == "apos") {
      out += '\'';
    } else {
      return std::nullopt;
    }
    i = semi;
  }
  return out;
}

}  // namespace

const std::string* XmlTag::attribute(std::string_view key) const noexcept {
  for (const auto& [k, v] : attributes) {
    if (k == key) return &v;
  }
  return nullptr;
}

XmlScanner::XmlScanner(std::string_view text, std::string file)
    : text_(text), file_(std::move(file)), pos_(bom_length(text)) {}

std::size_t XmlScanner::line_of(std::size_t offset) const noexcept {
  offset = std::min(offset, text_.size());
  // Callers ask in increasing order; count on from the last answer.
  if (offset < counted_offset_) {
    counted_offset_ = 0;
    counted_lines_ = 1;
  }
  counted_lines_ += static_cast<std::size_t>(
      std::count(text_.begin() + static_cast<std::ptrdiff_t>(counted_offset_),
                 text_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
  counted_offset_ = offset;
  return counted_lines_;
}

void XmlScanner::fail(std::size_t offset, const std::string& problem) const {
  ErrorContext ctx;
  ctx.file = file_;
  ctx.line = line_of(offset);
  throw_input_error(problem, ctx, "well-formed XML");
}

bool XmlScanner::next(XmlTag& tag, std::string_view& text_before) {
  const std::size_t text_start = pos_;
  for (;;) {
    const std::size_t lt = text_.find('<', pos_);
    if (lt == std::string_view::npos) {
      text_before = text_.substr(text_start);
      pos_ = text_.size();
      return false;
    }
    const std::string_view rest = text_.substr(lt);
    // Markup that carries nothing for us.
    const auto skip_to = [&](std::string_view end_marker) {
      const std::size_t end = text_.find(end_marker, lt);
      if (end == std::string_view::npos) fail(lt, "unterminated markup");
      pos_ = end + end_marker.size();
    };
    if (rest.substr(0, 4) == "<!--") {
      skip_to("-->");
      continue;
    }
    if (rest.substr(0, 2) == "<?") {
      skip_to("?>");
      continue;
    }
    if (rest.substr(0, 2) == "<!") {
      skip_to(">");
      continue;
    }
    text_before = text_.substr(text_start, lt - text_start);
    tag = XmlTag{};
    tag.begin = lt;
    std::size_t i = lt + 1;
    if (i < text_.size() && text_[i] == '/') {
      tag.closing = true;
      ++i;
    }
    const std::size_t name_start = i;
    while (i < text_.size() && is_name_char(text_[i])) ++i;
    tag.name = std::string(text_.substr(name_start, i - name_start));
    if (tag.name.empty()) fail(lt, "a '<' without a tag name");
    for (;;) {
      while (i < text_.size() && is_space(text_[i])) ++i;
      if (i >= text_.size()) fail(lt, fmt::format("tag <{}> is not closed", tag.name));
      if (text_[i] == '>') {
        pos_ = i + 1;
        return true;
      }
      if (text_[i] == '/' && i + 1 < text_.size() && text_[i + 1] == '>') {
        tag.self_closing = true;
        pos_ = i + 2;
        return true;
      }
      const std::size_t key_start = i;
      while (i < text_.size() && is_name_char(text_[i])) ++i;
      const std::string key(text_.substr(key_start, i - key_start));
      while (i < text_.size() && is_space(text_[i])) ++i;
      if (key.empty() || i >= text_.size() || text_[i] != '=') {
        fail(i, fmt::format("malformed attribute in <{}>", tag.name));
      }
      ++i;
      while (i < text_.size() && is_space(text_[i])) ++i;
      if (i >= text_.size() || (text_[i] != '"' && text_[i] != '\'')) {
        fail(i, fmt::format("attribute '{}' of <{}> has no quoted value", key, tag.name));
      }
      const char quote = text_[i];
      const std::size_t value_end = text_.find(quote, i + 1);
      if (value_end == std::string_view::npos) {
        fail(i, fmt::format("attribute '{}' of <{}> is not closed", key, tag.name));
      }
      auto value = unescape(text_.substr(i + 1, value_end - i - 1));
      if (!value) fail(i, fmt::format("unknown entity in attribute '{}'", key));
      tag.attributes.emplace_back(key, std::move(*value));
      i = value_end + 1;
    }
  }
}

std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace palpa::io_detail
