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

}  // namespace palpa::cli
