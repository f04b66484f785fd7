// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/samples.hpp"

#include <fmt/format.h>

#include "palpa/io/csv.hpp"

namespace palpa::mesh {

Samples read_samples(const std::filesystem::path& path, std::string_view value_base,
                     Dimension dimension) {
  const CsvTable table = read_csv(path);
  Samples s;
  s.source = path.string();
  const auto x = table.quantity("x", Dimension::Length);
  const auto y = table.quantity("y", Dimension::Length);
  const auto z = table.quantity("z", Dimension::Length);
  const auto v = table.quantity(value_base, dimension);
  for (const auto& name : table.names()) {
    if (split_quantity_name(name).base == value_base) s.field = name;
  }
  const auto n = static_cast<Eigen::Index>(table.rows());
  s.positions.resize(n, 3);
  s.values.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(i);
    s.positions.row(i) << x[r], y[r], z[r];
    s.values(i) = v[r];
    s.labels.push_back(fmt::format("the sample on line {}", table.line_of_row(r)));
  }
  return s;
}

}  // namespace palpa::mesh
