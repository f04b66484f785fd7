// Placeholder while the convert command is being written.
#include "commands.hpp"

namespace palpa::cli {

void add_convert_command(CLI::App& /*app*/) {}

}  // namespace palpa::cli
