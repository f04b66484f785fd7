// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/obj.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::LineCursor;

constexpr std::size_t kMaxListedGroups = 30;

struct PendingTriangle {
  io_detail::Triangle corners;  // 1-based, negative ones already resolved
  std::size_t line;
};

// The vertex index of one face corner ("7", "7/2", "7//3", "-1/2/3"), resolved
// to 1-based: a negative index counts back from the `defined` vertices so far.
long long corner_index(std::string_view token, long long defined, const LineCursor& at,
                       std::size_t corner) {
  const std::string_view vertex_part = token.substr(0, token.find('/'));
  const std::string field = fmt::format("face corner {} '{}'", corner, token);
  const auto index = parse_integer(vertex_part);
  if (!index) at.fail_field(field, "the vertex index is not an integer", "an integer vertex index");
  if (*index == 0) {
    at.fail_field(field, "vertex index 0 (OBJ counts vertices from 1)",
                  "an index from 1 to the number of vertices, or a negative one counting back");
  }
  if (*index > 0) return *index;
  const long long resolved = defined + *index + 1;
  if (resolved < 1) {
    at.fail_field(field,
                  fmt::format("relative vertex index {} reaches before the first vertex (only {} "
                              "vertices are defined above this line)",
                              *index, defined),
                  fmt::format("a negative index from -1 to -{}", defined));
  }
  return resolved;
}

}  // namespace

SurfaceMesh read_obj(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  const std::string bytes = io_detail::read_file_bytes(path);
  io_detail::require_content(bytes, file);
  LineCursor cursor(bytes, file);

  const bool filter = !options.obj_group.empty();
  std::vector<double> xyz;
  std::vector<PendingTriangle> triangles;
  std::vector<std::string> groups_seen;  // group and object names, first-seen order
  std::vector<std::string> current_groups{"default"};
  std::string current_object;
  bool selected = !filter;
  bool group_found = false;
  std::vector<int> poly;
  std::vector<io_detail::Triangle> fan;

  const auto note_name = [&](const std::string& name) {
    if (std::find(groups_seen.begin(), groups_seen.end(), name) == groups_seen.end()) {
      groups_seen.push_back(name);
    }
    if (filter && name == options.obj_group) group_found = true;
  };
  const auto update_selection = [&] {
    if (!filter) return;
    selected = current_object == options.obj_group ||
               std::find(current_groups.begin(), current_groups.end(), options.obj_group) !=
                   current_groups.end();
  };

  std::string_view line;
  while (cursor.next(line)) {
    const auto tokens = io_detail::tokens_of(line, '#');
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "v") {
      const long long n = static_cast<long long>(xyz.size() / 3) + 1;
      if (tokens.size() < 4) {
        cursor.fail_field(fmt::format("vertex {}", n),
                          fmt::format("{} coordinates", tokens.size() - 1), "v x y z");
      }
      for (std::size_t c = 0; c < 3; ++c) {
        xyz.push_back(io_detail::parse_number(tokens[c + 1], cursor,
                                              fmt::format("vertex {} {}", n, io_detail::kAxisNames[c])));
      }
      if (n > io_detail::kMaxIndex) cursor.fail("too many vertices for 32-bit indices");
    } else if (key == "f") {
      if (!selected) continue;
      if (tokens.size() < 4) {
        cursor.fail(fmt::format("face with {} corners", tokens.size() - 1),
                    "at least 3 vertex indices");
      }
      const long long defined = static_cast<long long>(xyz.size() / 3);
      poly.clear();
      for (std::size_t c = 1; c < tokens.size(); ++c) {
        const long long index = corner_index(tokens[c], defined, cursor, c);
        if (index > io_detail::kMaxIndex) {
          cursor.fail_field(fmt::format("face corner {} '{}'", c, tokens[c]),
                            fmt::format("vertex index {} is out of range", index));
        }
        poly.push_back(static_cast<int>(index));
      }
      fan.clear();
      io_detail::fan_triangulate(poly, fan);
      for (const auto& t : fan) triangles.push_back({t, cursor.line_number()});
    } else if (key == "g") {
      current_groups.assign(tokens.begin() + 1, tokens.end());
      if (current_groups.empty()) current_groups.emplace_back("default");
      for (const auto& g : current_groups) note_name(g);
      update_selection();
    } else if (key == "o") {
      // A new object starts outside any group.
      current_object = tokens.size() > 1 ? std::string(tokens[1]) : std::string();
      current_groups.assign(1, "default");
      if (!current_object.empty()) note_name(current_object);
      update_selection();
    }
    // Other statements (vt, vn, vp, usemtl, mtllib, s, l, p, ...) carry nothing
    // palpa uses.
  }

  ErrorContext ctx;
  ctx.file = file;
  if (filter && !group_found) {
    std::string names;
    for (std::size_t i = 0; i < groups_seen.size() && i < kMaxListedGroups; ++i) {
      names += (i > 0 ? ", " : "") + groups_seen[i];
    }
    if (groups_seen.size() > kMaxListedGroups) names += ", ...";
    throw_input_error(fmt::format("no group or object named '{}'; the file has: {}",
                                  options.obj_group, names.empty() ? "none" : names),
                      ctx, "one of the group names");
  }

  // Positive indices may refer to vertices defined further down; check them now.
  const long long vertex_count = static_cast<long long>(xyz.size() / 3);
  for (const PendingTriangle& t : triangles) {
    for (int c : t.corners) {
      if (c > vertex_count) {
        ErrorContext at = ctx;
        at.line = t.line;
        throw_input_error(fmt::format("vertex index {} is out of range: the file has {} vertices",
                                      c, vertex_count),
                          at, fmt::format("an index from 1 to {}", vertex_count));
      }
    }
  }
  if (triangles.empty()) {
    throw_input_error(filter ? fmt::format("group '{}' has no faces", options.obj_group)
                             : std::string("the mesh has no faces"),
                      ctx, "a mesh needs faces (f lines)");
  }

  SurfaceMesh mesh;
  std::vector<io_detail::Triangle> tris;
  tris.reserve(triangles.size());
  if (filter) {
    // Keep only the vertices the selected faces use, renumbered in file order.
    std::vector<int> new_index(static_cast<std::size_t>(vertex_count), -1);
    for (const auto& t : triangles) {
      for (int c : t.corners) new_index[static_cast<std::size_t>(c - 1)] = 0;
    }
    std::vector<double> kept;
    int next = 0;
    for (std::size_t v = 0; v < new_index.size(); ++v) {
      if (new_index[v] < 0) continue;
      new_index[v] = next++;
      kept.insert(kept.end(), xyz.begin() + static_cast<std::ptrdiff_t>(3 * v),
                  xyz.begin() + static_cast<std::ptrdiff_t>(3 * v + 3));
    }
    for (const auto& t : triangles) {
      tris.push_back({new_index[static_cast<std::size_t>(t.corners[0] - 1)],
                      new_index[static_cast<std::size_t>(t.corners[1] - 1)],
                      new_index[static_cast<std::size_t>(t.corners[2] - 1)]});
    }
    mesh.V = io_detail::positions_from(kept);
  } else {
    for (const auto& t : triangles) {
      tris.push_back({t.corners[0] - 1, t.corners[1] - 1, t.corners[2] - 1});
    }
    mesh.V = io_detail::positions_from(xyz);
  }
  mesh.F = io_detail::triangles_from(tris);
  io_detail::apply_unit(mesh.V, options, file);
  return mesh;
}

void write_obj(const std::filesystem::path& path, const SurfaceMesh& mesh) {
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
  std::string text = "# written by palpa\n";
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    fmt::format_to(std::back_inserter(text), "v {} {} {}\n", mesh.V(i, 0), mesh.V(i, 1),
                   mesh.V(i, 2));
  }
  for (Eigen::Index i = 0; i < mesh.F.rows(); ++i) {
    fmt::format_to(std::back_inserter(text), "f {} {} {}\n", mesh.F(i, 0) + 1, mesh.F(i, 1) + 1,
                   mesh.F(i, 2) + 1);
  }
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

}  // namespace palpa
