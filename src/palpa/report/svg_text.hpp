// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Text for XML documents (SVG now, the HTML report later).

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

}  // namespace palpa::report
