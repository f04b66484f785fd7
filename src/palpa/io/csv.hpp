// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Numeric CSV tables with units in the column names.
//
// Format: comma-separated, one header row of column names, then one row of
// numbers per line. Lines whose first non-blank character is '#' are comments;
// blank lines are skipped; CRLF line ends and a UTF-8 byte-order mark are
// accepted. A column that holds a physical quantity carries its unit after the
// last underscore of its name: `indentation_mm`, `force_gf`, `time_s`,
// `pressure_kPa` (units as in core/units.hpp). A column without an underscore is
// a plain number (`trial`, `stretch`). Every value must be a finite number.
//
//   # punch 4 mm, site forearm
//   time_s,indentation_mm,force_gf
//   0,0,0
//   0.1,0.25,12.5

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/units.hpp"

namespace palpa {

// A column name split at its last underscore: "force_gf" -> base "force",
// suffix "gf", unit gram-force. `unit` is nullptr when the name has no
// underscore (suffix empty) or the suffix is not a known unit.
struct QuantityName {
  std::string_view base;
  std::string_view suffix;
  const Unit* unit = nullptr;
};
QuantityName split_quantity_name(std::string_view column_name) noexcept;

// The dimension palpa expects for a well-known quantity name, judged by the
// base name or its last '_'-separated word: time -> Time; indentation, depth,
// displacement, thickness, radius -> Length; force, load -> Force; pressure,
// stress -> Pressure; mass -> Mass. nullopt for other names.
std::optional<Dimension> expected_dimension_of(std::string_view base) noexcept;

class CsvTable {
 public:
  CsvTable() = default;
  // An empty table whose errors name `source` (usually the file it describes).
  explicit CsvTable(std::string source) : source_(std::move(source)) {}

  // Appends a column. `name` must be non-empty, unique, without commas, quotes
  // or line breaks; `values` must have rows() entries unless the table has no
  // column yet (programmer errors: palpa::Error of kind Internal). Values are
  // stored as given.
  void add_column(std::string name, std::vector<double> values);
  // Appends the quantity column "<base>_<unit>" from SI values (converted to
  // `unit`, which must be a unit of dimension `d`): add_quantity("force", "gf",
  // Dimension::Force, {0.0098}) stores 1 (gf) in column force_gf.
  void add_quantity(std::string_view base, std::string_view unit, Dimension d,
                    const std::vector<double>& values_si);
  void add_comment(std::string text) { comments_.push_back(std::move(text)); }

  std::size_t rows() const noexcept { return columns_.empty() ? 0 : columns_.front().size(); }
  std::size_t column_count() const noexcept { return names_.size(); }
  // Column names in file order.
  const std::vector<std::string>& names() const noexcept { return names_; }
  // Comment lines (text after '#', leading space removed), in file order.
  const std::vector<std::string>& comments() const noexcept { return comments_; }
  // The file the table was read from ("" if built in memory).
  const std::string& source() const noexcept { return source_; }

  bool has_column(std::string_view name) const noexcept;
  // The values of column `name` (exact, case-sensitive match) as stored (file
  // units). Throws palpa::Error (Input) naming the file and listing the columns
  // present if there is no such column.
  const std::vector<double>& column(std::string_view name) const;
  // The values of column `index` (0-based, < column_count()).
  const std::vector<double>& column(std::size_t index) const { return columns_.at(index); }

  // The quantity column whose name is `base` + "_" + a unit of dimension `d`
  // (indentation_mm, indentation_m, ...), converted to SI: rows() values in the
  // SI unit of `d` (m, N, Pa, s, ...). Throws palpa::Error (Input) naming the
  // file, header line and column if there is no such column (listing those
  // present), if two columns share the base name, if the suffix is not a known
  // unit, or if the unit is of another kind (force_kg asked as a force).
  std::vector<double> quantity(std::string_view base, Dimension d) const;
  // As quantity(), but nullopt when no column has this base name (an optional
  // column); the other errors are still thrown.
  std::optional<std::vector<double>> find_quantity(std::string_view base, Dimension d) const;

  // 1-based line of data row `row` in the source file (0 if built in memory).
  std::size_t line_of_row(std::size_t row) const noexcept;
  // Where row `row` of column `name` is, for messages about values that are
  // numbers but wrong (negative force, decreasing time): file, line, column.
  ErrorContext context_of(std::size_t row, std::string_view name) const;

 private:
  friend CsvTable parse_csv(std::string_view text, const std::string& source);
  friend CsvTable csv_to_si(const CsvTable& table);

  std::optional<std::size_t> index_of(std::string_view name) const noexcept;
  ErrorContext header_context(std::size_t column_index) const;
  std::string column_list() const;

  std::string source_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
  std::vector<std::string> comments_;
  std::size_t header_line_ = 0;
  std::vector<std::size_t> row_lines_;
};

// Reads a CSV file (format above). Throws palpa::Error (Input) naming the file
// and, where there is one, the line and column: missing or empty file, no header
// row (first line holds numbers), empty or duplicate column names, a row with
// the wrong number of fields, an empty, non-numeric, NaN or infinite value, a
// header with no data rows. `use`: see read_input_file (RunState for a table
// the run adds to and writes back).
CsvTable read_csv(const std::filesystem::path& path, InputUse use = InputUse::Input);
// The same from text in memory; `source` names it in messages.
CsvTable parse_csv(std::string_view text, const std::string& source);

// Writes the table atomically: comments as "# ..." lines, the header, then the
// values in shortest round-trip form, so read_csv(write_csv(t)) returns the
// same doubles bit for bit. Throws palpa::Error (Internal) for a NaN/Inf value
// (naming column and row) and (Input) if the folder cannot be written.
void write_csv(const std::filesystem::path& path, const CsvTable& table);
// The text write_csv would write.
std::string format_csv(const CsvTable& table);

// A copy of `table` with every quantity column converted to SI: indentation_mm
// -> indentation_m (values x 1e-3), force_gf -> force_N, pressure_kPa ->
// pressure_Pa. Plain columns (no underscore) are copied; comments are kept.
// Throws palpa::Error (Input) naming the file and column for a suffix that is
// not a known unit, a unit of the wrong kind for a well-known quantity
// (force_kg: a mass unit for a force, see expected_dimension_of), or if two
// columns would get the same SI name.
CsvTable csv_to_si(const CsvTable& table);

}  // namespace palpa
