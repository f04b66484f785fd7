// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// JSON inputs (material files, datasets, subcommand configs) read through a view
// that remembers where it is: every error names the file and the field path
// ("material.json: parameters.E: ..."). Quantities are strings with units
// ("12 kPa") converted to SI here; plain numbers are accepted only where the
// quantity is dimensionless.

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/input_file.hpp"
#include "palpa/core/units.hpp"

namespace palpa {

using Json = nlohmann::json;

// Reads and parses a JSON file; a syntax error names the line and column.
// `use`: see read_input_file (RunState for a checkpoint the run rewrites).
Json read_json_file(const std::filesystem::path& path, InputUse use = InputUse::Input);

// Writes `j` pretty-printed (2-space indent), atomically.
void write_json_file(const std::filesystem::path& path, const Json& j);

// `j` pretty-printed (2-space indent) with a final newline, for an output
// file `path`. A NaN or infinity anywhere in it (which JSON cannot hold, and
// nlohmann would write as null) is an Internal error naming the file and the
// field, so no output hides a value that went wrong; a value that is not known
// is written as null on purpose instead.
std::string format_json(const Json& j, const std::filesystem::path& path);

// `v`, or null where it is not a finite number: for a value that may be
// undefined on purpose (an error over no points, the correlation of a uniform
// map).
inline Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

class JsonView {
 public:
  JsonView(const Json& j, std::string file, std::string path = {})
      : j_(&j), file_(std::move(file)), path_(std::move(path)) {}

  const Json& json() const noexcept { return *j_; }
  const std::string& file() const noexcept { return file_; }
  const std::string& path() const noexcept { return path_; }
  ErrorContext context() const;

  bool is_object() const noexcept { return j_->is_object(); }
  bool is_array() const noexcept { return j_->is_array(); }
  bool is_string() const noexcept { return j_->is_string(); }
  bool has(const std::string& key) const;

  // The member `key` of this object (error if missing or not an object).
  JsonView at(const std::string& key) const;
  std::optional<JsonView> find(const std::string& key) const;
  // Element i of this array.
  JsonView at(std::size_t i) const;
  std::size_t size() const;  // array length (error if not an array)

  std::string as_string() const;
  double as_number() const;  // a finite JSON number
  long long as_integer() const;
  bool as_bool() const;
  // A string with a unit converted to SI ("12 kPa" -> 12000). For dimensionless
  // quantities a JSON number is accepted too.
  double as_quantity(Dimension d) const;
  std::vector<double> as_number_array() const;

  // Fails if the object has members other than `allowed` (catches typos such as
  // "poisson" for "nu").
  void expect_only(const std::vector<std::string>& allowed) const;

  [[noreturn]] void fail(const std::string& problem, const std::string& expected = {}) const;

 private:
  const Json* j_;
  std::string file_;
  std::string path_;
};

}  // namespace palpa
