// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/csv.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

// How many column names a message lists before "...".
constexpr std::size_t kMaxListedColumns = 20;

// "m, cm, mm" — the unit symbols of one dimension, for "expected" texts.
std::string unit_symbols(Dimension d) {
  std::string out;
  for (const Unit& u : known_units()) {
    if (u.dimension != d) continue;
    if (!out.empty()) out += ", ";
    out += u.symbol;
  }
  return out;
}

std::string expected_quantity_name(std::string_view base, Dimension d) {
  return fmt::format("a column named {}_<unit> with a {} unit ({})", base, dimension_name(d),
                     unit_symbols(d));
}

// A header or value field: trimmed, surrounding double quotes removed.
std::string_view clean_field(std::string_view field) {
  field = trim(field);
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"') {
    field = trim(field.substr(1, field.size() - 2));
  }
  return field;
}

bool valid_column_name(std::string_view name) {
  return !name.empty() && name.find_first_of(",\"\r\n") == std::string_view::npos &&
         name.front() != '#';
}

}  // namespace

QuantityName split_quantity_name(std::string_view column_name) noexcept {
  QuantityName q;
  const std::size_t cut = column_name.rfind('_');
  if (cut == std::string_view::npos) {
    q.base = column_name;
    return q;
  }
  q.base = column_name.substr(0, cut);
  q.suffix = column_name.substr(cut + 1);
  q.unit = find_unit(q.suffix);
  return q;
}

std::optional<Dimension> expected_dimension_of(std::string_view base) noexcept {
  struct Known {
    std::string_view name;
    Dimension dimension;
  };
  static constexpr Known kKnown[] = {
      {"time", Dimension::Time},         {"indentation", Dimension::Length},
      {"depth", Dimension::Length},      {"displacement", Dimension::Length},
      {"thickness", Dimension::Length},  {"radius", Dimension::Length},
      {"force", Dimension::Force},       {"load", Dimension::Force},
      {"pressure", Dimension::Pressure}, {"stress", Dimension::Pressure},
      {"mass", Dimension::Mass},
  };
  const std::size_t cut = base.rfind('_');
  const std::string_view last = cut == std::string_view::npos ? base : base.substr(cut + 1);
  for (const Known& k : kKnown) {
    if (k.name == base || k.name == last) return k.dimension;
  }
  return std::nullopt;
}

void CsvTable::add_column(std::string name, std::vector<double> values) {
  if (!valid_column_name(name) || index_of(name) ||
      (!columns_.empty() && values.size() != rows())) {
    throw Error(ErrorKind::Internal,
                fmt::format("cannot add column '{}' ({} values) to a table with columns {} ({} "
                            "rows): names must be unique, non-empty, without , \" or line "
                            "breaks, and columns of equal length",
                            name, values.size(), column_list(), rows()),
                ErrorContext{source_, 0, 0, {}});
  }
  names_.push_back(std::move(name));
  columns_.push_back(std::move(values));
}

void CsvTable::add_quantity(std::string_view base, std::string_view unit, Dimension d,
                            const std::vector<double>& values_si) {
  std::vector<double> values;
  values.reserve(values_si.size());
  for (double v : values_si) values.push_back(si_to_unit(v, unit, d));
  add_column(fmt::format("{}_{}", base, unit), std::move(values));
}

bool CsvTable::has_column(std::string_view name) const noexcept {
  return index_of(name).has_value();
}

std::optional<std::size_t> CsvTable::index_of(std::string_view name) const noexcept {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return i;
  }
  return std::nullopt;
}

std::string CsvTable::column_list() const {
  if (names_.empty()) return "none";
  std::string out;
  for (std::size_t i = 0; i < names_.size() && i < kMaxListedColumns; ++i) {
    if (i > 0) out += ", ";
    out += names_[i];
  }
  if (names_.size() > kMaxListedColumns) out += ", ...";
  return out;
}

ErrorContext CsvTable::header_context(std::size_t column_index) const {
  ErrorContext ctx;
  ctx.file = source_;
  ctx.line = header_line_;
  ctx.column = column_index + 1;
  ctx.field = fmt::format("column '{}'", names_[column_index]);
  return ctx;
}

const std::vector<double>& CsvTable::column(std::string_view name) const {
  if (const auto i = index_of(name)) return columns_[*i];
  ErrorContext ctx;
  ctx.file = source_;
  ctx.line = header_line_;
  throw_input_error(fmt::format("no column '{}'; the columns are: {}", name, column_list()), ctx,
                    fmt::format("a column named {}", name));
}

std::optional<std::vector<double>> CsvTable::find_quantity(std::string_view base,
                                                           Dimension d) const {
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const QuantityName q = split_quantity_name(names_[i]);
    if (q.suffix.empty() || q.base != base) continue;
    if (found) {
      throw_input_error(fmt::format("columns '{}' and '{}' both hold {}; keep one", names_[*found],
                                    names_[i], base),
                        header_context(i), expected_quantity_name(base, d));
    }
    found = i;
  }
  if (!found) return std::nullopt;
  const std::size_t i = *found;
  const QuantityName q = split_quantity_name(names_[i]);
  if (q.unit == nullptr) {
    std::string hint;
    for (const Unit& u : known_units()) {
      if (u.dimension == d && to_lower(u.symbol) == to_lower(q.suffix)) {
        hint = fmt::format("; did you mean '{}'?", u.symbol);
        break;
      }
    }
    throw_input_error(fmt::format("unknown unit '{}'{}", q.suffix, hint), header_context(i),
                      expected_quantity_name(base, d));
  }
  if (q.unit->dimension != d) {
    throw_input_error(fmt::format("unit '{}' is a {} unit, not a {} unit", q.suffix,
                                  dimension_name(q.unit->dimension), dimension_name(d)),
                      header_context(i), expected_quantity_name(base, d));
  }
  std::vector<double> out;
  out.reserve(rows());
  for (double v : columns_[i]) out.push_back(v * q.unit->to_si);
  return out;
}

std::vector<double> CsvTable::quantity(std::string_view base, Dimension d) const {
  if (auto values = find_quantity(base, d)) return std::move(*values);
  ErrorContext ctx;
  ctx.file = source_;
  ctx.line = header_line_;
  const std::string problem = index_of(base)
                                  ? fmt::format("column '{}' has no unit", base)
                                  : fmt::format("no column for {} ({}); the columns are: {}", base,
                                                dimension_name(d), column_list());
  throw_input_error(
      problem, ctx,
      fmt::format("{}, e.g. {}_{}", expected_quantity_name(base, d), base, si_unit(d)));
}

std::size_t CsvTable::line_of_row(std::size_t row) const noexcept {
  return row < row_lines_.size() ? row_lines_[row] : 0;
}

ErrorContext CsvTable::context_of(std::size_t row, std::string_view name) const {
  ErrorContext ctx;
  ctx.file = source_;
  ctx.line = line_of_row(row);
  if (const auto i = index_of(name)) ctx.column = *i + 1;
  ctx.field = fmt::format("column '{}'", name);
  return ctx;
}

CsvTable parse_csv(std::string_view text, const std::string& source) {
  CsvTable table(source);
  io_detail::LineCursor cursor(text, source);
  std::string_view line;
  bool have_header = false;
  std::vector<std::vector<double>> columns;
  while (cursor.next(line)) {
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (t.front() == '#') {
      table.comments_.emplace_back(trim(t.substr(1)));
      continue;
    }
    const std::vector<std::string_view> fields = split(line, ',');
    if (!have_header) {
      have_header = true;
      table.header_line_ = cursor.line_number();
      bool all_numbers = true;
      for (std::string_view f : fields) all_numbers = all_numbers && parse_finite_double(f);
      if (all_numbers) {
        cursor.fail("missing header: the first line holds numbers, not column names",
                    "a header row such as indentation_mm,force_N");
      }
      for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::string_view name = clean_field(fields[i]);
        ErrorContext ctx = cursor.here();
        ctx.column = i + 1;
        if (name.empty()) {
          throw_input_error(fmt::format("column {} has an empty name", i + 1), ctx,
                            "a name for every column, such as force_N");
        }
        if (name.find(';') != std::string_view::npos) {
          ctx.field = fmt::format("column '{}'", name);
          throw_input_error("the column name contains ';'", ctx,
                            "comma-separated columns (palpa reads ',' as the separator)");
        }
        for (std::size_t j = 0; j < table.names_.size(); ++j) {
          if (table.names_[j] == name) {
            ctx.field = fmt::format("column '{}'", name);
            throw_input_error(fmt::format("duplicate column name (also column {})", j + 1), ctx,
                              "distinct column names");
          }
        }
        table.names_.emplace_back(name);
      }
      columns.resize(fields.size());
      continue;
    }
    if (fields.size() != table.names_.size()) {
      cursor.fail(fmt::format("row has {} fields but the header has {} columns ({})", fields.size(),
                              table.names_.size(), table.column_list()),
                  fmt::format("{} comma-separated numbers", table.names_.size()));
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string_view value = clean_field(fields[i]);
      if (const auto v = parse_finite_double(value)) {
        columns[i].push_back(*v);
        continue;
      }
      ErrorContext ctx = cursor.here();
      ctx.column = i + 1;
      ctx.field = fmt::format("column '{}'", table.names_[i]);
      throw_input_error(io_detail::number_problem(value), ctx, "a finite number");
    }
    table.row_lines_.push_back(cursor.line_number());
  }
  if (!have_header) {
    ErrorContext ctx;
    ctx.file = source;
    throw_input_error(text.empty() ? "file is empty" : "file holds no header and no data", ctx,
                      "a header row such as indentation_mm,force_N and rows of numbers");
  }
  if (table.row_lines_.empty()) {
    ErrorContext ctx;
    ctx.file = source;
    ctx.line = table.header_line_;
    throw_input_error("the header is not followed by any data row", ctx,
                      "rows of comma-separated numbers after the header");
  }
  table.columns_ = std::move(columns);
  return table;
}

CsvTable read_csv(const std::filesystem::path& path, InputUse use) {
  const std::string bytes = io_detail::read_file_bytes(path, false, use);
  return parse_csv(bytes, path.string());
}

std::string format_csv(const CsvTable& table) {
  std::string out;
  for (const std::string& c : table.comments()) {
    out += c.empty() ? "#" : "# ";
    out += c;
    out += '\n';
  }
  for (std::size_t i = 0; i < table.column_count(); ++i) {
    if (i > 0) out += ',';
    out += table.names()[i];
  }
  out += '\n';
  for (std::size_t r = 0; r < table.rows(); ++r) {
    for (std::size_t i = 0; i < table.column_count(); ++i) {
      const double v = table.column(i)[r];
      if (!std::isfinite(v)) {
        throw Error(ErrorKind::Internal,
                    fmt::format("value {} in row {} cannot be written to CSV", v, r + 1),
                    table.context_of(r, table.names()[i]));
      }
      if (i > 0) out += ',';
      fmt::format_to(std::back_inserter(out), "{}", v);
    }
    out += '\n';
  }
  return out;
}

void write_csv(const std::filesystem::path& path, const CsvTable& table) {
  std::string text;
  try {
    text = format_csv(table);
  } catch (const Error& e) {
    ErrorContext ctx = e.context();
    ctx.file = path.string();
    ctx.line = 0;
    throw Error(e.kind(), e.problem(), ctx, e.expected());
  }
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

CsvTable csv_to_si(const CsvTable& table) {
  CsvTable out(table.source());
  for (const std::string& c : table.comments()) out.add_comment(c);
  for (std::size_t i = 0; i < table.column_count(); ++i) {
    const std::string& name = table.names()[i];
    const QuantityName q = split_quantity_name(name);
    ErrorContext ctx;
    ctx.file = table.source();
    ctx.line = table.header_line_;
    ctx.column = i + 1;
    ctx.field = fmt::format("column '{}'", name);
    std::string si_name = name;
    std::vector<double> values = table.column(i);
    if (!q.suffix.empty()) {
      if (q.unit == nullptr) {
        throw_input_error(fmt::format("unknown unit '{}'", q.suffix), ctx,
                          "a name ending in a unit such as _mm, _N, _kPa, _s (see `palpa "
                          "units`), or a name without '_' for a plain number");
      }
      const auto expected = expected_dimension_of(q.base);
      if (expected && *expected != q.unit->dimension) {
        // Scales read in kilograms or grams: the force unit is kgf or gf.
        const Unit* force_unit = find_unit(fmt::format("{}f", q.suffix));
        const std::string hint =
            *expected == Dimension::Force && force_unit != nullptr &&
                    force_unit->dimension == Dimension::Force
                ? fmt::format("; for a force read off a scale use '{}f'", q.suffix)
                : std::string();
        throw_input_error(
            fmt::format("unit '{}' is a {} unit, but {} is a {}{}", q.suffix,
                        dimension_name(q.unit->dimension), q.base, dimension_name(*expected), hint),
            ctx, expected_quantity_name(q.base, *expected));
      }
      const std::string_view si = si_unit(q.unit->dimension);
      si_name = si.empty() ? std::string(q.base) : fmt::format("{}_{}", q.base, si);
      for (std::size_t r = 0; r < values.size(); ++r) {
        const double si_value = values[r] * q.unit->to_si;
        if (!std::isfinite(si_value)) {
          throw_input_error(fmt::format("{:g} {} is beyond the range of a number in {}", values[r], q.suffix,
                                        si.empty() ? std::string("SI units") : std::string(si)),
                            table.context_of(r, name), "a finite value");
        }
        values[r] = si_value;
      }
    }
    if (out.has_column(si_name)) {
      throw_input_error(fmt::format("becomes '{}' in SI, like an earlier column", si_name), ctx,
                        "one column per quantity");
    }
    out.add_column(std::move(si_name), std::move(values));
  }
  out.header_line_ = table.header_line_;
  out.row_lines_ = table.row_lines_;
  return out;
}

}  // namespace palpa
