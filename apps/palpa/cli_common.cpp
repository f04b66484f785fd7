#include "cli_common.hpp"

#include <fmt/format.h>

#include "palpa/core/error.hpp"

namespace palpa::cli {

CLI::Option* add_quantity_option(CLI::App& app, const std::string& name, double& target,
                                 Dimension dimension, const std::string& description) {
  const std::string help = fmt::format("{} [{}]", description, dimension_example(dimension));
  auto* opt = app.add_option_function<std::string>(
      name,
      [&target, dimension, name](const std::string& text) {
        ErrorContext where;
        where.field = fmt::format("option {}", name);
        try {
          target = parse_quantity(text, dimension, where);
        } catch (const Error& e) {
          throw CLI::ValidationError(name, std::string(e.problem()) + " (expected " +
                                               e.expected() + ")");
        }
      },
      help);
  opt->type_name(dimension == Dimension::Dimensionless ? "NUMBER" : "QUANTITY");
  return opt;
}

void require_empty_output(const std::filesystem::path& out, std::string_view what) {
  std::error_code ec;
  if (std::filesystem::is_directory(out, ec) && !std::filesystem::is_empty(out, ec)) {
    throw_input_error(fmt::format("output folder '{}' is not empty", out.string()),
                      ErrorContext{out.string(), 0, 0, "option -o"},
                      fmt::format("a new or empty folder, --resume to continue an interrupted {} there, or --overwrite",
                                  what));
  }
}

}  // namespace palpa::cli
