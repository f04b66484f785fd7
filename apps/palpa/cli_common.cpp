// SPDX-License-Identifier: AGPL-3.0-or-later
#include "cli_common.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <utility>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/text.hpp"

namespace palpa::cli {

CLI::Option* add_quantity_option(CLI::App& app, const std::string& name, double& target,
                                 Dimension dimension, const std::string& description, Sign sign) {
  const std::string help = fmt::format("{} [{}]", description, dimension_example(dimension));
  auto* opt = app.add_option_function<std::string>(
      name,
      [&target, dimension, name, sign](const std::string& text) {
        ErrorContext where;
        where.field = fmt::format("option {}", name);
        double value = 0.0;
        try {
          value = parse_quantity(text, dimension, where);
        } catch (const Error& e) {
          throw CLI::ValidationError(name, std::string(e.problem()) + " (expected " +
                                               e.expected() + ")");
        }
        if ((sign == Sign::Positive && !(value > 0.0)) || (sign == Sign::NonNegative && !(value >= 0.0))) {
          throw CLI::ValidationError(name, fmt::format("{} is {} (expected a {} value)", text,
                                                       value < 0.0 ? "negative" : "zero",
                                                       sign == Sign::Positive ? "positive" : "non-negative"));
        }
        target = value;
      },
      help);
  opt->type_name(dimension == Dimension::Dimensionless ? "NUMBER" : "QUANTITY");
  return opt;
}

CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(value) || value < lo || value > hi) {
          return fmt::format("{} is not in range [{:g} - {:g}] (a finite number)", text, lo, hi);
        }
        return {};
      },
      fmt::format("NUMBER in [{:g} - {:g}]", lo, hi));
}

std::pair<double, double> parse_range(const std::string& text, const std::string& option, const std::string& example) {
  ErrorContext where;
  where.field = fmt::format("option {}", option);
  const auto parts = split(text, ':');
  if (parts.size() != 2) throw_input_error(fmt::format("'{}' is not a range", text), where, "LOW:HIGH, e.g. " + example);
  const auto lo = parse_finite_double(parts[0]);
  const auto hi = parse_finite_double(parts[1]);
  if (!lo || !hi || !(*hi > *lo)) {
    throw_input_error(fmt::format("'{}' is not an increasing range of numbers", text), where,
                      "LOW:HIGH with LOW < HIGH, e.g. " + example);
  }
  return {*lo, *hi};
}

namespace {

struct PathRoles {
  std::vector<std::string> inputs, outputs;
};

std::map<const CLI::App*, PathRoles>& path_registry() {
  static std::map<const CLI::App*, PathRoles> registry;
  return registry;
}

// The file a value names, spelled one way: absolute, with links, "." and
// ".." resolved as far as the path exists.
std::filesystem::path same_file_key(std::string value, bool named) {
  if (const auto eq = value.find('='); named && eq != std::string::npos) value = value.substr(eq + 1);
  std::error_code ec;
  std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(value, ec), ec);
  if (ec) p = std::filesystem::absolute(value).lexically_normal();
  return p;
}

void check_command(const CLI::App& cmd) {
  if (const auto it = path_registry().find(&cmd); it != path_registry().end()) {
    struct Seen {
      std::string option, value;
      bool output;
    };
    std::map<std::filesystem::path, Seen> seen;
    const auto visit = [&](const std::vector<std::string>& names, bool output) {
      for (std::string name : names) {
        const bool named = !name.empty() && name.back() == '=';
        if (named) name.pop_back();
        const CLI::Option* opt = cmd.get_option_no_throw(name);
        if (opt == nullptr) continue;
        for (const std::string& value : opt->results()) {
          if (value.empty()) {
            throw_input_error("an empty path", ErrorContext{"", 0, 0, fmt::format("option {}", opt->get_name())},
                              output ? "a path to write to (or leave the option out)" : "a path to read");
          }
          if (output) {
            refuse_special_output(value, ErrorContext{value, 0, 0, fmt::format("option {}", opt->get_name())});
          }
          const auto key = same_file_key(value, named);
          const auto [at, fresh] = seen.emplace(key, Seen{opt->get_name(), value, output});
          if (fresh || !(output || at->second.output)) continue;
          const Seen& first = at->second;
          throw_input_error(
              fmt::format("{} '{}' is the same file as {} '{}': palpa {} would {}", opt->get_name(), value,
                          first.option, first.value, cmd.get_name(),
                          first.output && output ? "write both outputs into it, one over the other"
                                                 : "overwrite its input with its output"),
              ErrorContext{value, 0, 0, fmt::format("option {}", opt->get_name())},
              "a path for each output that is no input and no other output");
        }
      }
    };
    visit(it->second.inputs, false);
    visit(it->second.outputs, true);
  }
  for (const CLI::App* sub : cmd.get_subcommands()) check_command(*sub);
}

}  // namespace

void declare_paths(const CLI::App& cmd, std::vector<std::string> inputs, std::vector<std::string> outputs) {
  path_registry()[&cmd] = PathRoles{std::move(inputs), std::move(outputs)};
}

void check_distinct_paths(const CLI::App& app) { check_command(app); }

}  // namespace palpa::cli
