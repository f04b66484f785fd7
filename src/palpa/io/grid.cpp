// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/grid.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

Eigen::MatrixXd read_number_grid(const std::filesystem::path& path) {
  const std::string text = io_detail::read_file_bytes(path);
  io_detail::LineCursor cursor(text, path.string());
  std::vector<std::vector<double>> rows;
  std::string_view line;
  while (cursor.next_content(line)) {
    std::vector<double> row;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      const std::string_view token =
          line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
      row.push_back(
          io_detail::parse_number(token, cursor, fmt::format("field {}", row.size() + 1)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (!rows.empty() && row.size() != rows.front().size()) {
      cursor.fail(
          fmt::format("{} fields where the first row has {}", row.size(), rows.front().size()),
          "rows of equal length");
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty())
    throw Error(ErrorKind::Input, "no rows of numbers", ErrorContext{path.string(), 0, 0, {}},
                "a grid");
  Eigen::MatrixXd grid(static_cast<Eigen::Index>(rows.size()),
                       static_cast<Eigen::Index>(rows.front().size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < rows[r].size(); ++c)
      grid(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
  }
  return grid;
}

}  // namespace palpa
