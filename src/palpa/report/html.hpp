// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A report as one self-contained HTML file: headings, text, tables and
// pictures, opened from the output folder in any browser. Pictures (SVG) are
// embedded as data: URIs, so that the ids inside each (gradients, clip paths)
// cannot clash, and the file needs nothing beside it: no scripts, no fonts,
// no network.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace palpa::report {

class HtmlReport {
 public:
  // title: the page's title and first heading; subtitle: a line under it.
  explicit HtmlReport(std::string title, std::string subtitle = {});

  void heading(const std::string& text);      // a section
  void subheading(const std::string& text);   // within a section
  void paragraph(const std::string& text);    // plain text (escaped)
  // A table: header cells and rows of cells (plain text, escaped); numbers
  // right-aligned when a column's cells all read as numbers.
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // Pictures side by side (wrapping on a narrow window): SVG documents with
  // a caption each.
  struct Picture {
    std::string svg;
    std::string caption;
  };
  void pictures(const std::vector<Picture>& row);
  // SVG files as pictures side by side; a missing file gives a line saying
  // so instead (a report of a run that did not get that far).
  void picture_files(const std::vector<std::pair<std::filesystem::path, std::string>>& row);

  std::string html() const;
  // Writes it atomically.
  void write(const std::filesystem::path& path) const;

 private:
  std::string title_;
  std::string body_;
};

// Text with &, <, >, " escaped for HTML.
std::string html_escape(const std::string& text);

}  // namespace palpa::report
