// SPDX-License-Identifier: AGPL-3.0-or-later
#include "report/xml_check.hpp"

#include <cctype>
#include <stdexcept>

#include "palpa/core/text.hpp"

namespace palpa::test {
namespace {

bool name_start(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':' ||
         static_cast<unsigned char>(c) >= 0x80;
}
bool name_char(char c) {
  return name_start(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.';
}
bool space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

void append_utf8(std::string& out, unsigned long cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

class Reader {
 public:
  explicit Reader(std::string_view t) : t_(t) {}

  XmlDocument run() {
    XmlDocument doc;
    try {
      read(doc);
    } catch (const std::runtime_error& e) {
      doc.error = std::string(e.what()) + " at byte " + std::to_string(i_);
    }
    return doc;
  }

 private:
  [[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }
  bool at(std::string_view s) const { return t_.substr(i_, s.size()) == s; }
  void skip_space() {
    while (i_ < t_.size() && space(t_[i_])) ++i_;
  }
  std::string name() {
    if (i_ >= t_.size() || !name_start(t_[i_])) fail("expected a name");
    const std::size_t b = i_;
    while (i_ < t_.size() && name_char(t_[i_])) ++i_;
    return std::string(t_.substr(b, i_ - b));
  }
  // Decodes text up to `stop` (exclusive), checking entities.
  std::string decode(std::string_view raw) {
    std::string out;
    for (std::size_t k = 0; k < raw.size(); ++k) {
      const char c = raw[k];
      if (c == '<') fail("'<' in text or attribute");
      if (c != '&') {
        out += c;
        continue;
      }
      const std::size_t semi = raw.find(';', k);
      if (semi == std::string_view::npos) fail("'&' without ';'");
      const std::string_view ent = raw.substr(k + 1, semi - k - 1);
      if (ent == "amp")
        out += '&';
      else if (ent == "lt")
        out += '<';
      else if (ent == "gt")
        out += '>';
      else if (ent == "quot")
        out += '"';
      else if (ent == "apos")
        out += '\'';
      else if (ent.size() > 1 && ent[0] == '#') {
        const bool hex = ent[1] == 'x';
        const auto digits = std::string(ent.substr(hex ? 2 : 1));
        if (digits.empty()) fail("empty character reference");
        std::size_t used = 0;
        const unsigned long cp = std::stoul(digits, &used, hex ? 16 : 10);
        if (used != digits.size()) fail("bad character reference");
        append_utf8(out, cp);
      } else {
        fail("unknown entity &" + std::string(ent) + ";");
      }
      k = semi;
    }
    return out;
  }

  void read(XmlDocument& doc) {
    if (at("<?xml")) {
      const std::size_t e = t_.find("?>", i_);
      if (e == std::string_view::npos) fail("unterminated XML declaration");
      i_ = e + 2;
    }
    std::vector<int> open;
    bool root_done = false;
    while (true) {
      const std::size_t lt = t_.find('<', i_);
      const std::string_view raw = t_.substr(i_, lt == std::string_view::npos ? t_.npos : lt - i_);
      if (raw.find("]]>") != std::string_view::npos) fail("']]>' in text");
      const std::string text = decode(raw);
      if (open.empty()) {
        for (char c : text)
          if (!space(c)) fail("text outside the root element");
      } else {
        doc.elements[static_cast<std::size_t>(open.back())].text += text;
      }
      if (lt == std::string_view::npos) break;
      i_ = lt;
      if (at("<!--")) {
        const std::size_t e = t_.find("-->", i_);
        if (e == std::string_view::npos) fail("unterminated comment");
        i_ = e + 3;
        continue;
      }
      if (at("</")) {
        i_ += 2;
        const std::string n = name();
        skip_space();
        if (!at(">")) fail("expected '>' after </" + n);
        ++i_;
        if (open.empty() || doc.elements[static_cast<std::size_t>(open.back())].name != n)
          fail("unmatched </" + n + ">");
        open.pop_back();
        if (open.empty()) root_done = true;
        continue;
      }
      ++i_;
      if (root_done) fail("second root element");
      XmlElement e;
      e.name = name();
      e.parent = open.empty() ? -1 : open.back();
      while (true) {
        const std::size_t before = i_;
        skip_space();
        if (at("/>") || at(">")) break;
        if (i_ == before) fail("expected space before attribute");
        const std::string key = name();
        skip_space();
        if (!at("=")) fail("expected '=' after " + key);
        ++i_;
        skip_space();
        if (i_ >= t_.size() || (t_[i_] != '"' && t_[i_] != '\'')) fail("unquoted attribute " + key);
        const char q = t_[i_++];
        const std::size_t end = t_.find(q, i_);
        if (end == std::string_view::npos) fail("unterminated attribute " + key);
        if (!e.attributes.emplace(key, decode(t_.substr(i_, end - i_))).second)
          fail("duplicate attribute " + key);
        i_ = end + 1;
      }
      const bool self_closing = at("/>");
      i_ += self_closing ? 2 : 1;
      doc.elements.push_back(std::move(e));
      if (self_closing) {
        if (open.empty()) root_done = true;
      } else {
        open.push_back(static_cast<int>(doc.elements.size() - 1));
      }
    }
    if (!open.empty())
      fail("unclosed <" + doc.elements[static_cast<std::size_t>(open.back())].name + ">");
    if (!root_done) fail("no root element");
  }

  std::string_view t_;
  std::size_t i_ = 0;
};

}  // namespace

std::vector<const XmlElement*> XmlDocument::all(std::string_view name,
                                                std::string_view ancestor_class) const {
  std::vector<const XmlElement*> out;
  for (const auto& e : elements) {
    if (e.name != name) continue;
    bool match = ancestor_class.empty();
    for (int p = e.parent; !match && p >= 0; p = elements[static_cast<std::size_t>(p)].parent) {
      const auto& attrs = elements[static_cast<std::size_t>(p)].attributes;
      const auto it = attrs.find("class");
      match = it != attrs.end() && it->second == ancestor_class;
    }
    if (match) out.push_back(&e);
  }
  return out;
}

double XmlDocument::number(const XmlElement& e, const std::string& attribute) {
  const auto it = e.attributes.find(attribute);
  if (it == e.attributes.end()) throw std::runtime_error("no attribute " + attribute);
  const auto v = parse_finite_double(it->second);
  if (!v) throw std::runtime_error("attribute " + attribute + " is not a number: " + it->second);
  return *v;
}

XmlDocument parse_xml(std::string_view text) {
  return Reader(text).run();
}

}  // namespace palpa::test
