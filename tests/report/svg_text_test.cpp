// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/svg_text.hpp"

#include <gtest/gtest.h>

namespace palpa::report {
namespace {

TEST(ReportSvgText, EscapesMarkupCharacters) {
  EXPECT_EQ(escape_xml("a<b & \"c\" 'd' >"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos; &gt;");
  EXPECT_EQ(escape_xml("plain text 1.5 mm"), "plain text 1.5 mm");
  EXPECT_EQ(escape_xml(""), "");
}

TEST(ReportSvgText, KeepsValidUtf8) {
  const std::string s =
      "force \xE2\x80\x93 indentation, 10\xE2\x81\xBB\xE2\x81\xB6, \xCE\xBC m, \xF0\x9F\x98\x80";
  EXPECT_EQ(escape_xml(s), s);
}

TEST(ReportSvgText, ReplacesWhatXmlCannotHold) {
  const std::string fffd = "\xEF\xBF\xBD";
  EXPECT_EQ(escape_xml(std::string("a\x01"
                                   "b")),
            "a" + fffd + "b");
  EXPECT_EQ(escape_xml(std::string("a\0b", 3)), "a" + fffd + "b");
  EXPECT_EQ(escape_xml("tab\tand\nline"), "tab\tand\nline");
  EXPECT_EQ(escape_xml("\xFF"
                       "x"),
            fffd + "x");                                      // not UTF-8
  EXPECT_EQ(escape_xml("\xC3"), fffd);                        // truncated sequence
  EXPECT_EQ(escape_xml("\xC0\xAF"), fffd + fffd);             // overlong '/'
  EXPECT_EQ(escape_xml("\xED\xA0\x80"), fffd + fffd + fffd);  // surrogate
  EXPECT_EQ(escape_xml("\xEF\xBF\xBF"), fffd);                // U+FFFF
}

TEST(ReportSvgText, CountsCodePoints) {
  EXPECT_EQ(utf8_length(""), 0u);
  EXPECT_EQ(utf8_length("abc"), 3u);
  EXPECT_EQ(utf8_length("10\xE2\x81\xBB\xE2\x81\xB6"), 4u);  // 10⁻⁶
  EXPECT_EQ(utf8_length("\xFF\xFE"), 2u);
}

TEST(ReportSvgText, WritesNumbersToATenthOfAPixel) {
  EXPECT_EQ(svg_number(12.34), "12.3");
  EXPECT_EQ(svg_number(40.0), "40");
  EXPECT_EQ(svg_number(-0.5), "-0.5");
  EXPECT_EQ(svg_number(-0.04), "0");
  EXPECT_EQ(svg_number(0.96), "1");
}

TEST(ReportSvgText, WritesEscapedTextElements) {
  SvgWriter svg;
  svg.begin(100, 50.25);
  svg.text(1.25, 2, "a<b", 11, "middle", "fill=\"#222\"");
  svg.end();
  const std::string& s = svg.str();
  EXPECT_NE(s.find("width=\"100\" height=\"50.3\" viewBox=\"0 0 100 50.3\""), std::string::npos)
      << s;
  EXPECT_NE(s.find("<text x=\"1.3\" y=\"2\" font-size=\"11\" text-anchor=\"middle\" "
                   "fill=\"#222\">a&lt;b</text>"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.substr(s.size() - 7), "</svg>\n");
  EXPECT_DOUBLE_EQ(estimated_text_width("10 kPa", 10), 36.0);
}

}  // namespace
}  // namespace palpa::report
