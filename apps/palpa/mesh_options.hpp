// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What the `palpa mesh` subcommands share (tet quality options, length units,
// the --edge bound, the output folder check) and the registration of each
// (cmd_mesh_<name>.cpp).

#include <CLI/CLI.hpp>

#include <filesystem>
#include <numbers>
#include <string>

#include "palpa/core/error.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace palpa::cli {

inline constexpr double kDegree = std::numbers::pi / 180.0;

struct QualityArgs {
  double max_radius_edge = 1.5;
  double min_dihedral = 12.0 * kDegree;
  double tet_size = 0.0;  // edge of a regular tet of the largest volume [m]; 0 = default
};

// The context of an error about option `name` ("--edge").
ErrorContext option_context(const std::string& name);

// A surface of `area` remeshed to --edge: refused by the option's name when it
// would make more triangles than palpa makes (mesh::kMaxRemeshTriangles).
void check_edge_for(double area, double edge, const std::string& what);

// Metres per coordinate unit: a unit symbol ("mm") or a length ("0.1 m").
double length_unit(const std::string& text);

mesh::TetQuality quality_from(const QualityArgs& q);
void add_quality_options(CLI::App& cmd, QualityArgs& q);

// The folder `target` goes into; refused if it does not exist. Checked before
// the meshing too, so that a typo in -o does not cost the whole run.
std::filesystem::path existing_folder_of(const std::filesystem::path& target);

void add_mesh_layer(CLI::App& mesh);
void add_mesh_body(CLI::App& mesh);
void add_mesh_solid(CLI::App& mesh);

}  // namespace palpa::cli
