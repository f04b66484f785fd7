// Placeholder while the material command is being written.
#include "commands.hpp"

namespace palpa::cli {

void add_material_command(CLI::App& /*app*/) {}

}  // namespace palpa::cli
