// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One registration function per subcommand; each lives in cmd_<name>.cpp and
// attaches a CLI11 subcommand whose callback calls into the library.

#include <CLI/CLI.hpp>

namespace palpa::cli {

void add_units_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_material_command(CLI::App& app);
// palpa material show / models / curve (cmd_material_inspect.cpp).
void add_material_inspection(CLI::App& material);
void add_demo_command(CLI::App& app);
void add_poke_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_sim3d_command(CLI::App& app);
void add_rest_command(CLI::App& app);
void add_design_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_mesh_command(CLI::App& app);
void add_acquire_command(CLI::App& app);
void add_subject_command(CLI::App& app);

}  // namespace palpa::cli
