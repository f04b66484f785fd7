// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa mesh solid: a solid tet mesh of the inside of a closed surface.

#include <spdlog/spdlog.h>

#include <memory>
#include <string>

#include "cli_common.hpp"
#include "mesh_options.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/mesh/layer.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/mesh/tetrahedralize.hpp"

namespace palpa::cli {

namespace {

struct SolidArgs {
  std::string surface;
  std::string unit;
  double edge = 0.0;
  QualityArgs quality;
  std::string output;
};

void run_solid(const SolidArgs& a) {
  MeshReadOptions read;
  read.unit_to_si = length_unit(a.unit);
  SurfaceMesh s = mesh::repair_surface(read_surface_mesh(a.surface, read));
  existing_folder_of(a.output);
  mesh::check_closed_surface(s, a.surface);
  if (a.edge > 0.0) {
    check_edge_for(mesh::surface_area(s), a.edge, a.surface);
    s = mesh::remesh_surface(s, a.edge);
  }
  const mesh::TetQuality q = quality_from(a.quality);
  const TetMesh tets = mesh::tetrahedralize(s, q);
  const mesh::TetStatistics st = mesh::tet_statistics(tets, q);
  write_tet_mesh(a.output, tets);
  spdlog::info("wrote {}: {} tets, {} vertices, min dihedral {:.1f} deg, max radius-edge {:.2f}",
               a.output, st.tets, st.vertices, st.min_dihedral / kDegree, st.max_radius_edge);
}

}  // namespace

void add_mesh_solid(CLI::App& mesh) {
  auto sa = std::make_shared<SolidArgs>();
  auto* solid = mesh.add_subcommand("solid", "Solid tet mesh of the inside of a closed surface.");
  solid->add_option("--surface", sa->surface, "Closed surface (.obj .ply .stl .off .vtu)")
      ->required();
  solid->add_option("--unit", sa->unit, "Length unit of the surface's coordinates (default m)")
      ->type_name("UNIT");
  add_quantity_option(*solid, "--edge", sa->edge, Dimension::Length,
                      "Remesh the surface to this edge length first (default: keep it)");
  add_quality_options(*solid, sa->quality);
  solid->add_option("-o,--output", sa->output, "Output tet mesh (.vtu, .node, .msh)")->required();
  declare_paths(*solid, {"--surface"}, {"-o"});
  solid->callback([sa] { run_solid(*sa); });
}

}  // namespace palpa::cli
