// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/html.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fmt/format.h>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/base64.hpp"

namespace palpa::report {

namespace {

constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 2em auto; max-width: 1200px; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.3em; border-bottom: 1px solid #ccc; margin-top: 2em; }
h3 { font-size: 1.1em; margin-top: 1.4em; }
.subtitle { color: #666; margin-top: 0; }
table { border-collapse: collapse; margin: 0.8em 0; }
th, td { border: 1px solid #ddd; padding: 0.25em 0.6em; }
th { background: #f3f3f3; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.row { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
figure { margin: 0.5em 0; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { color: #555; font-size: 0.9em; }
.missing { color: #a33; }
)";

bool reads_as_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  // A number, maybe with a unit or a percent sign after a space.
  return end != s.c_str() && (*end == '\0' || *end == ' ' || *end == '%');
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

HtmlReport::HtmlReport(std::string title, std::string subtitle) : title_(std::move(title)) {
  body_ += fmt::format("<h1>{}</h1>\n", html_escape(title_));
  if (!subtitle.empty()) body_ += fmt::format("<p class=\"subtitle\">{}</p>\n", html_escape(subtitle));
}

void HtmlReport::heading(const std::string& text) { body_ += fmt::format("<h2>{}</h2>\n", html_escape(text)); }

void HtmlReport::subheading(const std::string& text) { body_ += fmt::format("<h3>{}</h3>\n", html_escape(text)); }

void HtmlReport::paragraph(const std::string& text) { body_ += fmt::format("<p>{}</p>\n", html_escape(text)); }

void HtmlReport::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::vector<bool> numeric(header.size(), !rows.empty());
  for (const auto& r : rows) {
    for (std::size_t c = 0; c < header.size(); ++c) {
      if (c >= r.size() || !reads_as_number(r[c])) numeric[c] = false;
    }
  }
  body_ += "<table>\n<tr>";
  for (const std::string& h : header) body_ += fmt::format("<th>{}</th>", html_escape(h));
  body_ += "</tr>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (std::size_t c = 0; c < header.size(); ++c) {
      const std::string cell = c < r.size() ? r[c] : "";
      body_ += fmt::format("<td{}>{}</td>", numeric[c] ? " class=\"num\"" : "", html_escape(cell));
    }
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::pictures(const std::vector<Picture>& row) {
  body_ += "<div class=\"row\">\n";
  for (const Picture& p : row) {
    body_ += fmt::format("<figure><img alt=\"{0}\" src=\"data:image/svg+xml;base64,{1}\"><figcaption>{0}</figcaption>"
                         "</figure>\n",
                         html_escape(p.caption), base64_encode(p.svg));
  }
  body_ += "</div>\n";
}

void HtmlReport::picture_files(const std::vector<std::pair<std::filesystem::path, std::string>>& row) {
  std::vector<Picture> found;
  for (const auto& [svg, caption] : row) {
    if (std::filesystem::is_regular_file(svg)) {
      found.push_back({read_input_file(svg), caption});
    } else {
      body_ += fmt::format("<p class=\"missing\">{}: not made ({} is missing)</p>\n", html_escape(caption),
                           html_escape(svg.string()));
    }
  }
  if (!found.empty()) pictures(found);
}

std::string HtmlReport::html() const {
  return fmt::format("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                     "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                     "<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n{}</body>\n</html>\n",
                     html_escape(title_), kStyle, body_);
}

void HtmlReport::write(const std::filesystem::path& path) const {
  write_file_atomic(path, [&](std::ostream& o) { o << html(); });
}

}  // namespace palpa::report
