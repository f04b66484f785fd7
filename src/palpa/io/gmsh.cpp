// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/gmsh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <unordered_map>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::LineCursor;

constexpr int kTypeTriangle = 2;
constexpr int kTypeTetrahedron = 4;
constexpr const char* kExportHint =
    "Gmsh format 4.1 ASCII (in Gmsh: File > Export > .msh, 'Version 4 ASCII'; or "
    "gmsh -format msh41 without -bin)";

// Nodes per element for the linear types palpa reads or skips; 0 = not supported.
int nodes_per_element(long long type) {
  switch (type) {
    case 1:
      return 2;  // line
    case 2:
      return 3;  // triangle
    case 3:
      return 4;  // quadrangle
    case 4:
      return 4;  // tetrahedron
    case 5:
      return 8;  // hexahedron
    case 6:
      return 6;  // prism
    case 7:
      return 5;  // pyramid
    case 15:
      return 1;  // point
    default:
      return 0;
  }
}

template <std::size_t N>
struct Cell {
  long long tag;
  std::array<int, N> nodes;
  int label;
};

class MshReader {
 public:
  MshReader(const std::string& bytes, std::string file) : cursor_(bytes, std::move(file)) {}

  TetMesh read() {
    read_format();
    std::string_view line;
    while (cursor_.next_content(line, '\0')) {
      const std::string_view t = trim(line);
      if (t.front() != '$') {
        cursor_.fail(fmt::format("unexpected line '{}' between sections", t.substr(0, 40)),
                     "a section start such as $Nodes");
      }
      const std::string name(t.substr(1));
      if (name == "Entities") {
        read_entities();
      } else if (name == "Nodes") {
        read_nodes();
      } else if (name == "Elements") {
        read_elements();
      } else if (name == "MeshFormat") {
        cursor_.fail("a second $MeshFormat section");
      } else {
        skip_section(name);
        continue;
      }
      expect_end(name);
    }
    return assemble();
  }

 private:
  std::vector<std::string_view> content_line(const char* expected) {
    std::string_view line;
    if (!cursor_.next_content(line, '\0')) {
      cursor_.fail("the file ends inside a section", expected);
    }
    return split_whitespace(line);
  }

  std::vector<std::string_view> tokens(std::size_t min_count, const char* expected) {
    auto t = content_line(expected);
    if (t.size() < min_count) {
      cursor_.fail(fmt::format("{} values on the line, expected at least {}", t.size(), min_count),
                   expected);
    }
    return t;
  }

  long long count(std::string_view token, const char* what) {
    const long long n = io_detail::parse_int(token, cursor_, what);
    if (n < 0 || n > io_detail::kMaxIndex) {
      cursor_.fail_field(what, fmt::format("{} is out of range", n));
    }
    return n;
  }

  void expect_end(const std::string& name) {
    std::string_view line;
    const std::string end = "$End" + name;
    if (!cursor_.next_content(line, '\0') || trim(line) != end) {
      cursor_.fail(fmt::format("section ${} is not closed where its counts say it ends", name),
                   end);
    }
  }

  void skip_section(const std::string& name) {
    const std::string end = "$End" + name;
    std::string_view line;
    while (cursor_.next(line)) {
      if (trim(line) == end) return;
    }
    cursor_.fail(fmt::format("section ${} has no {}", name, end));
  }

  void read_format() {
    std::string_view line;
    if (!cursor_.next_content(line, '\0') || trim(line) != "$MeshFormat") {
      cursor_.fail(
          fmt::format("not a Gmsh .msh file: the first line is '{}'", trim(line).substr(0, 40)),
          "$MeshFormat");
    }
    const auto t = tokens(3, "version file-type data-size, e.g. 4.1 0 8");
    if (t[0] != "4.1") {
      cursor_.fail(fmt::format("Gmsh format version {} is not supported", t[0]), kExportHint);
    }
    if (t[1] != "0") {
      cursor_.fail("binary .msh files are not supported", kExportHint);
    }
    expect_end("MeshFormat");
  }

  void read_entities() {
    const auto n = tokens(4, "numPoints numCurves numSurfaces numVolumes");
    for (std::size_t dim = 0; dim < 4; ++dim) {
      const long long entities = count(n[dim], "entity count");
      for (long long e = 0; e < entities; ++e) {
        const char* expected = dim == 0 ? "tag x y z numPhysicalTags tags..."
                                        : "tag minX minY minZ maxX maxY maxZ numPhysicalTags "
                                          "tags... numBounding tags...";
        const auto t = tokens(dim == 0 ? 5 : 9, expected);
        const long long tag = io_detail::parse_int(t[0], cursor_, "entity tag");
        const std::size_t at = dim == 0 ? 4 : 7;
        const long long physicals = count(t[at], "number of physical tags");
        const std::size_t needed =
            at + 1 + static_cast<std::size_t>(physicals) + (dim == 0 ? 0 : 1);
        if (t.size() < needed) {
          cursor_.fail(fmt::format("{} values on the line, the entity needs {}", t.size(), needed),
                       expected);
        }
        int physical = 0;
        if (physicals > 0) {
          physical = static_cast<int>(io_detail::parse_int(t[at + 1], cursor_, "physical tag"));
        }
        physical_[dim][tag] = physical;
      }
    }
  }

  void read_nodes() {
    if (have_nodes_) cursor_.fail("a second $Nodes section");
    have_nodes_ = true;
    const auto h = tokens(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
    const long long blocks = count(h[0], "number of node blocks");
    const long long total = count(h[1], "number of nodes");
    std::size_t read = 0;
    std::vector<long long> tags;
    for (long long b = 0; b < blocks; ++b) {
      const auto bh = tokens(4, "entityDim entityTag parametric numNodesInBlock");
      io_detail::parse_int(bh[2], cursor_, "parametric");
      const long long n = count(bh[3], "number of nodes in block");
      tags.clear();
      for (long long i = 0; i < n; ++i) {
        const auto t = tokens(1, "nodeTag");
        tags.push_back(io_detail::parse_int(t[0], cursor_, "node tag"));
      }
      // Parametric nodes carry u [v [w]] after x y z; only x y z are used.
      for (long long i = 0; i < n; ++i) {
        const auto t = tokens(3, "x y z");
        const long long tag = tags[static_cast<std::size_t>(i)];
        const auto [it, inserted] = node_index_.try_emplace(tag, static_cast<int>(xyz_.size() / 3));
        if (!inserted) cursor_.fail_field(fmt::format("node {}", tag), "duplicate node tag");
        for (std::size_t c = 0; c < 3; ++c) {
          xyz_.push_back(
              io_detail::parse_number(t[c], cursor_, fmt::format("node {} {}", tag, io_detail::kAxisNames[c])));
        }
      }
      read += static_cast<std::size_t>(n);
    }
    if (read != static_cast<std::size_t>(total)) {
      cursor_.fail(
          fmt::format("the node blocks hold {} nodes, the $Nodes header says {}", read, total));
    }
  }

  int node(std::string_view token, long long element_tag) {
    const long long tag = io_detail::parse_int(token, cursor_, "node tag");
    const auto it = node_index_.find(tag);
    if (it == node_index_.end()) {
      cursor_.fail_field(fmt::format("element {}", element_tag),
                         fmt::format("node {} is not in $Nodes", tag));
    }
    return it->second;
  }

  int physical_of(std::size_t dim, long long entity) {
    const auto it = physical_[dim].find(entity);
    return it == physical_[dim].end() ? 0 : it->second;
  }

  void read_elements() {
    if (!have_nodes_) cursor_.fail("$Elements comes before $Nodes", "$Nodes first");
    const auto h = tokens(4, "numEntityBlocks numElements minElementTag maxElementTag");
    const long long blocks = count(h[0], "number of element blocks");
    for (long long b = 0; b < blocks; ++b) {
      const auto bh = tokens(4, "entityDim entityTag elementType numElementsInBlock");
      const long long dim = io_detail::parse_int(bh[0], cursor_, "entity dimension");
      const long long entity = io_detail::parse_int(bh[1], cursor_, "entity tag");
      const long long type = io_detail::parse_int(bh[2], cursor_, "element type");
      const long long n = count(bh[3], "number of elements in block");
      const int per = nodes_per_element(type);
      if (per == 0) {
        cursor_.fail_field("element type",
                           fmt::format("element type {} is not supported (second-order or "
                                       "unknown)",
                                       type),
                           "linear elements: 4-node tetrahedra (type 4), 3-node triangles (2)");
      }
      if (dim < 0 || dim > 3) cursor_.fail_field("entity dimension", fmt::format("{}", dim));
      const int label = physical_of(static_cast<std::size_t>(dim), entity);
      for (long long i = 0; i < n; ++i) {
        const auto t = tokens(static_cast<std::size_t>(1 + per), "elementTag nodeTag...");
        const long long tag = io_detail::parse_int(t[0], cursor_, "element tag");
        if (type == kTypeTetrahedron) {
          Cell<4> c{tag, {}, label};
          for (std::size_t k = 0; k < 4; ++k) c.nodes[k] = node(t[k + 1], tag);
          tets_.push_back(c);
          any_region_ = any_region_ || label != 0;
        } else if (type == kTypeTriangle) {
          Cell<3> c{tag, {}, label};
          for (std::size_t k = 0; k < 3; ++k) c.nodes[k] = node(t[k + 1], tag);
          triangles_.push_back(c);
          any_marker_ = any_marker_ || label != 0;
        } else {
          for (int k = 0; k < per; ++k) node(t[static_cast<std::size_t>(k + 1)], tag);
        }
      }
    }
  }

  TetMesh assemble() {
    ErrorContext ctx;
    ctx.file = cursor_.file();
    if (tets_.empty()) {
      throw_input_error(
          triangles_.empty()
              ? "the mesh has no tetrahedra"
              : fmt::format("the mesh has no tetrahedra (only {} triangles)", triangles_.size()),
          ctx, "a tet mesh with 4-node tetrahedra (element type 4)");
    }
    const auto by_tag = [](const auto& a, const auto& b) { return a.tag < b.tag; };
    std::stable_sort(tets_.begin(), tets_.end(), by_tag);
    std::stable_sort(triangles_.begin(), triangles_.end(), by_tag);
    TetMesh mesh;
    mesh.V = io_detail::positions_from(xyz_);
    const auto nt = static_cast<Eigen::Index>(tets_.size());
    mesh.T.resize(nt, 4);
    if (any_region_) mesh.region.resize(nt);
    for (Eigen::Index i = 0; i < nt; ++i) {
      const auto& c = tets_[static_cast<std::size_t>(i)];
      for (int k = 0; k < 4; ++k) mesh.T(i, k) = c.nodes[static_cast<std::size_t>(k)];
      if (any_region_) mesh.region[i] = c.label;
    }
    const auto nb = static_cast<Eigen::Index>(triangles_.size());
    mesh.boundary.resize(nb, 3);
    if (any_marker_) mesh.boundary_marker.resize(nb);
    for (Eigen::Index i = 0; i < nb; ++i) {
      const auto& c = triangles_[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k) mesh.boundary(i, k) = c.nodes[static_cast<std::size_t>(k)];
      if (any_marker_) mesh.boundary_marker[i] = c.label;
    }
    return mesh;
  }

  LineCursor cursor_;
  bool have_nodes_ = false;
  std::array<std::unordered_map<long long, int>, 4> physical_;
  std::unordered_map<long long, int> node_index_;
  std::vector<double> xyz_;
  std::vector<Cell<4>> tets_;
  std::vector<Cell<3>> triangles_;
  bool any_region_ = false;
  bool any_marker_ = false;
};

// Entities of one dimension: one per distinct label (first-appearance order).
struct EntityGroup {
  int label;
  std::vector<Eigen::Index> cells;
};

template <class Labels>
std::vector<EntityGroup> group_by_label(Eigen::Index count, const Labels& labels) {
  std::vector<EntityGroup> groups;
  std::map<int, std::size_t> slot;
  for (Eigen::Index i = 0; i < count; ++i) {
    const int label = labels.size() > 0 ? labels[i] : 0;
    const auto [it, inserted] = slot.try_emplace(label, groups.size());
    if (inserted) groups.push_back({label, {}});
    groups[it->second].cells.push_back(i);
  }
  return groups;
}

template <class Cells>
void write_entity(std::string& out, std::size_t tag, const EntityGroup& g, const Cells& cells,
                  const Eigen::MatrixX3d& V) {
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(0.0);
  Eigen::RowVector3d hi = Eigen::RowVector3d::Constant(0.0);
  bool first = true;
  for (Eigen::Index c : g.cells) {
    for (Eigen::Index k = 0; k < cells.cols(); ++k) {
      const Eigen::RowVector3d p = V.row(cells(c, k));
      lo = first ? p : Eigen::RowVector3d(lo.cwiseMin(p));
      hi = first ? p : Eigen::RowVector3d(hi.cwiseMax(p));
      first = false;
    }
  }
  fmt::format_to(std::back_inserter(out), "{} {} {} {} {} {} {} ", tag, lo[0], lo[1], lo[2], hi[0],
                 hi[1], hi[2]);
  if (g.label > 0) {
    fmt::format_to(std::back_inserter(out), "1 {} 0\n", g.label);
  } else {
    out += "0 0\n";
  }
}

}  // namespace

TetMesh read_gmsh(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  const std::string bytes = io_detail::read_file_bytes(path);
  io_detail::require_content(bytes, file);
  MshReader reader(bytes, file);
  TetMesh mesh = reader.read();
  io_detail::apply_unit(mesh.V, options, file);
  return mesh;
}

void write_gmsh(const std::filesystem::path& path, const TetMesh& mesh) {
  const auto volumes = group_by_label(mesh.T.rows(), mesh.region);
  const auto surfaces = mesh.boundary.rows() > 0
                            ? group_by_label(mesh.boundary.rows(), mesh.boundary_marker)
                            : std::vector<EntityGroup>{};
  std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  fmt::format_to(std::back_inserter(out), "$Entities\n0 0 {} {}\n", surfaces.size(),
                 volumes.size());
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    write_entity(out, s + 1, surfaces[s], mesh.boundary, mesh.V);
  }
  for (std::size_t v = 0; v < volumes.size(); ++v) {
    write_entity(out, v + 1, volumes[v], mesh.T, mesh.V);
  }
  out += "$EndEntities\n";

  const Eigen::Index nv = mesh.V.rows();
  fmt::format_to(std::back_inserter(out), "$Nodes\n1 {} 1 {}\n3 1 0 {}\n", nv, nv, nv);
  for (Eigen::Index i = 0; i < nv; ++i) fmt::format_to(std::back_inserter(out), "{}\n", i + 1);
  for (Eigen::Index i = 0; i < nv; ++i) {
    fmt::format_to(std::back_inserter(out), "{} {} {}\n", mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
  }
  out += "$EndNodes\n";

  const Eigen::Index nt = mesh.T.rows();
  const Eigen::Index total = nt + mesh.boundary.rows();
  fmt::format_to(std::back_inserter(out), "$Elements\n{} {} 1 {}\n",
                 volumes.size() + surfaces.size(), total, total);
  for (std::size_t v = 0; v < volumes.size(); ++v) {
    fmt::format_to(std::back_inserter(out), "3 {} {} {}\n", v + 1, kTypeTetrahedron,
                   volumes[v].cells.size());
    for (Eigen::Index t : volumes[v].cells) {
      fmt::format_to(std::back_inserter(out), "{} {} {} {} {}\n", t + 1, mesh.T(t, 0) + 1,
                     mesh.T(t, 1) + 1, mesh.T(t, 2) + 1, mesh.T(t, 3) + 1);
    }
  }
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    fmt::format_to(std::back_inserter(out), "2 {} {} {}\n", s + 1, kTypeTriangle,
                   surfaces[s].cells.size());
    for (Eigen::Index b : surfaces[s].cells) {
      fmt::format_to(std::back_inserter(out), "{} {} {} {}\n", nt + b + 1, mesh.boundary(b, 0) + 1,
                     mesh.boundary(b, 1) + 1, mesh.boundary(b, 2) + 1);
    }
  }
  out += "$EndElements\n";
  write_file_atomic(path, [&](std::ostream& s) { s << out; });
}

}  // namespace palpa
