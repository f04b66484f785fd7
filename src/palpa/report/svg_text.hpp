// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Text for XML documents (SVG now, the HTML report later), and the few pieces
// every SVG figure of the report module writes alike: numbers rounded to
// 0.1 px, escaped <text> elements, the document's opening with its white
// background, and an estimate of how wide a label is.

#include <cstddef>
#include <string>
#include <string_view>

namespace palpa::report {

// `text` made safe as XML character data or a quoted attribute value: & < > " '
// become entities; control characters other than tab, LF and CR, the
// non-characters U+FFFE/U+FFFF and bytes that are not valid UTF-8 become U+FFFD.
std::string escape_xml(std::string_view text);

// Number of Unicode code points in UTF-8 `text` (invalid bytes count one each).
std::size_t utf8_length(std::string_view text) noexcept;

// The font stack of every figure.
inline constexpr const char* kSvgFontFamily = "'DejaVu Sans', Helvetica, Arial, sans-serif";

// A coordinate or length [px] rounded to 0.1 px, shortest form: "12.3", "40",
// "-0.5" ("-0" becomes "0").
std::string svg_number(double v);

// Estimated advance [px] of `text` at font size `size` [px] (sans-serif,
// digits ≈ 0.6 em), for laying out labels before a renderer sees them.
double estimated_text_width(std::string_view text, double size);

// An SVG document being written: strings go in as they are, doubles as
// svg_number().
class SvgWriter {
 public:
  SvgWriter& operator<<(std::string_view s) {
    out_ += s;
    return *this;
  }
  SvgWriter& operator<<(double v) {
    out_ += svg_number(v);
    return *this;
  }
  // The XML declaration, the <svg> element of width × height px (viewBox in
  // px, the font stack) and a white background; close it with end().
  void begin(double width, double height);
  void end() { out_ += "</svg>\n"; }
  // <text> with escaped content. size <= 0 and anchor "" inherit them from the
  // enclosing group; anchor: start, middle, end; `extra`: more attributes,
  // written as given.
  void text(double x, double y, std::string_view content, double size, std::string_view anchor,
            std::string_view extra = {});
  std::string& str() noexcept { return out_; }

 private:
  std::string out_;
};

}  // namespace palpa::report
