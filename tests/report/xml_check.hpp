// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A small, strict XML reader for the report tests: checks that a document is
// well formed (one root, matched tags, quoted and unique attributes, only the
// five predefined entities and character references, no stray '<' or '&') and
// returns its elements in document order with decoded attributes and text.

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace palpa::test {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  // decoded values
  std::string text;                               // decoded character data directly inside
  int parent = -1;                                // index in XmlDocument::elements
};

struct XmlDocument {
  std::vector<XmlElement> elements;
  std::string error;  // empty if well formed
  bool ok() const { return error.empty(); }

  // Elements named `name`, optionally only those with an ancestor whose class
  // attribute is `ancestor_class`.
  std::vector<const XmlElement*> all(std::string_view name,
                                     std::string_view ancestor_class = {}) const;
  // Attribute as a number (throws std::runtime_error if missing or not a number).
  static double number(const XmlElement& e, const std::string& attribute);
};

XmlDocument parse_xml(std::string_view text);

}  // namespace palpa::test
