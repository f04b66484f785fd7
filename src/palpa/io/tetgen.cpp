// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/tetgen.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::LineCursor;


// A region attribute: TetGen writes integers, some tools write 1.0; anything
// else is refused.
int integral_attribute(std::string_view token, const LineCursor& at, const std::string& what) {
  const double v = io_detail::parse_number(token, at, what);
  if (v != std::floor(v) || std::abs(v) > io_detail::kMaxIndex) {
    at.fail_field(what, fmt::format("region attribute {} is not an integer", token),
                  "an integer region id");
  }
  return static_cast<int>(v);
}

std::vector<std::string_view> header_line(LineCursor& cursor, std::size_t min_tokens,
                                          const char* expected) {
  std::string_view line;
  if (!cursor.next_content(line)) cursor.fail("the file has no header line", expected);
  auto tokens = io_detail::tokens_of(line);
  if (tokens.size() < min_tokens) cursor.fail("malformed header line", expected);
  return tokens;
}

long long count_field(std::string_view token, const LineCursor& at, const std::string& what,
                      long long max) {
  const long long n = io_detail::parse_int(token, at, what);
  if (n < 0 || n > max) at.fail_field(what, fmt::format("{} is out of range", n));
  return n;
}

// Reads `index` plus `n` numbers from the next content line of `cursor`.
std::vector<std::string_view> record(LineCursor& cursor, std::size_t tokens_needed, long long i,
                                     long long count, const char* what) {
  std::string_view line;
  if (!cursor.next_content(line)) {
    cursor.fail(fmt::format("the file ends after {} of {} {}", i, count, what));
  }
  auto tokens = io_detail::tokens_of(line);
  if (tokens.size() < tokens_needed) {
    cursor.fail(
        fmt::format("{} values on the line, the header asks for {}", tokens.size(), tokens_needed));
  }
  return tokens;
}

}  // namespace

std::filesystem::path tetgen_stem(const std::filesystem::path& path) {
  const std::string ext = to_lower(path.extension().string());
  if (ext == ".node" || ext == ".ele" || ext == ".face") {
    return path.parent_path() / path.stem();
  }
  return path;
}

TetMesh read_tetgen(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::filesystem::path stem = tetgen_stem(path);
  const std::filesystem::path node_path = stem.string() + ".node";
  const std::filesystem::path ele_path = stem.string() + ".ele";
  const std::filesystem::path face_path = stem.string() + ".face";
  TetMesh mesh;

  // .node
  const std::string node_bytes = io_detail::read_file_bytes(node_path);
  io_detail::require_content(node_bytes, node_path.string());
  LineCursor nodes(node_bytes, node_path.string());
  const char* node_header = "#points 3 #attributes #boundary-markers";
  auto h = header_line(nodes, 2, node_header);
  const long long nv = count_field(h[0], nodes, "point count", io_detail::kMaxIndex);
  if (io_detail::parse_int(h[1], nodes, "dimension") != 3) {
    nodes.fail_field("dimension", fmt::format("dimension {}", h[1]), "3");
  }
  const long long node_attrs = h.size() > 2 ? count_field(h[2], nodes, "attribute count", 1000) : 0;
  const long long node_markers = h.size() > 3 ? count_field(h[3], nodes, "marker count", 1) : 0;
  const auto limit = static_cast<long long>(node_bytes.size() / 2 + 1);
  std::vector<double> xyz;
  xyz.reserve(static_cast<std::size_t>(3 * std::min(nv, limit)));
  long long base = 0;
  const auto node_tokens = static_cast<std::size_t>(4 + node_attrs + node_markers);
  for (long long i = 0; i < nv; ++i) {
    const auto t = record(nodes, node_tokens, i, nv, "points");
    const long long number = io_detail::parse_int(t[0], nodes, "point number");
    if (i == 0) {
      if (number != 0 && number != 1) {
        nodes.fail_field("point number", fmt::format("the first point is numbered {}", number),
                         "0 or 1");
      }
      base = number;
    } else if (number != base + i) {
      nodes.fail_field(
          "point number",
          fmt::format("point number {} breaks the sequence (expected {})", number, base + i),
          "consecutive point numbers");
    }
    for (std::size_t c = 0; c < 3; ++c) {
      xyz.push_back(
          io_detail::parse_number(t[c + 1], nodes, fmt::format("point {} {}", number, io_detail::kAxisNames[c])));
    }
  }
  mesh.V = io_detail::positions_from(xyz);

  const auto node_index = [&](std::string_view token, const LineCursor& at,
                              const std::string& what) {
    const long long number = io_detail::parse_int(token, at, what);
    if (number < base || number >= base + nv) {
      at.fail_field(what, fmt::format("point {} does not exist", number),
                    fmt::format("a point number from {} to {}", base, base + nv - 1));
    }
    return static_cast<int>(number - base);
  };

  // .ele
  const std::string ele_bytes = io_detail::read_file_bytes(ele_path);
  io_detail::require_content(ele_bytes, ele_path.string());
  LineCursor eles(ele_bytes, ele_path.string());
  h = header_line(eles, 2, "#tetrahedra 4 #attributes");
  const long long nt = count_field(h[0], eles, "tetrahedron count", io_detail::kMaxIndex);
  const long long per_tet = io_detail::parse_int(h[1], eles, "nodes per tetrahedron");
  if (per_tet != 4) {
    eles.fail_field("nodes per tetrahedron", fmt::format("{} nodes per tetrahedron", per_tet),
                    "4 (linear tets; quadratic tets are not supported)");
  }
  const long long tet_attrs = h.size() > 2 ? count_field(h[2], eles, "attribute count", 1000) : 0;
  if (nt == 0) {
    eles.fail("the mesh has no tetrahedra", "a tet mesh needs tetrahedra");
  }
  const auto ele_limit = static_cast<std::size_t>(ele_bytes.size() / 2 + 1);
  std::vector<int> corners;
  std::vector<int> regions;
  corners.reserve(4 * std::min(static_cast<std::size_t>(nt), ele_limit));
  for (long long i = 0; i < nt; ++i) {
    const auto t = record(eles, static_cast<std::size_t>(5 + tet_attrs), i, nt, "tetrahedra");
    for (std::size_t c = 0; c < 4; ++c) {
      corners.push_back(
          node_index(t[c + 1], eles, fmt::format("tetrahedron {} corner {}", t[0], c + 1)));
    }
    if (tet_attrs > 0) {
      regions.push_back(integral_attribute(t[5], eles, fmt::format("tetrahedron {} region", t[0])));
    }
  }
  mesh.T = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>>(
      corners.data(), static_cast<Eigen::Index>(nt), 4);
  if (tet_attrs > 0) {
    mesh.region = Eigen::Map<const Eigen::VectorXi>(regions.data(), static_cast<Eigen::Index>(nt));
  }

  // .face (optional)
  std::error_code ec;
  if (std::filesystem::exists(face_path, ec)) {
    const std::string face_bytes = io_detail::read_file_bytes(face_path, /*allow_empty=*/true);
    io_detail::require_content(face_bytes, face_path.string());
    LineCursor faces(face_bytes, face_path.string());
    h = header_line(faces, 1, "#faces #boundary-markers");
    const long long nb = count_field(h[0], faces, "face count", io_detail::kMaxIndex);
    const long long markers = h.size() > 1 ? count_field(h[1], faces, "marker count", 1) : 0;
    const auto face_limit = static_cast<std::size_t>(face_bytes.size() / 2 + 1);
    std::vector<int> tri;
    std::vector<int> marks;
    tri.reserve(3 * std::min(static_cast<std::size_t>(nb), face_limit));
    for (long long i = 0; i < nb; ++i) {
      const auto t = record(faces, static_cast<std::size_t>(4 + markers), i, nb, "faces");
      for (std::size_t c = 0; c < 3; ++c) {
        tri.push_back(node_index(t[c + 1], faces, fmt::format("face {} corner {}", t[0], c + 1)));
      }
      if (markers > 0) {
        const long long m = io_detail::parse_int(t[4], faces, fmt::format("face {} marker", t[0]));
        if (std::abs(m) > io_detail::kMaxIndex) {
          faces.fail_field(fmt::format("face {} marker", t[0]), "marker out of range");
        }
        marks.push_back(static_cast<int>(m));
      }
    }
    mesh.boundary = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        tri.data(), static_cast<Eigen::Index>(nb), 3);
    if (markers > 0) {
      mesh.boundary_marker =
          Eigen::Map<const Eigen::VectorXi>(marks.data(), static_cast<Eigen::Index>(nb));
    }
  }
  io_detail::apply_unit(mesh.V, options, node_path.string());
  return mesh;
}

void write_tetgen(const std::filesystem::path& path, const TetMesh& mesh) {
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
  const std::filesystem::path stem = tetgen_stem(path);
  std::string node = fmt::format("# written by palpa\n{} 3 0 0\n", mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    fmt::format_to(std::back_inserter(node), "{} {} {} {}\n", i + 1, mesh.V(i, 0), mesh.V(i, 1),
                   mesh.V(i, 2));
  }
  const bool has_region = mesh.region.size() > 0;
  std::string ele = fmt::format("# written by palpa\n{} 4 {}\n", mesh.T.rows(), has_region ? 1 : 0);
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t) {
    fmt::format_to(std::back_inserter(ele), "{} {} {} {} {}", t + 1, mesh.T(t, 0) + 1,
                   mesh.T(t, 1) + 1, mesh.T(t, 2) + 1, mesh.T(t, 3) + 1);
    if (has_region) fmt::format_to(std::back_inserter(ele), " {}", mesh.region[t]);
    ele += '\n';
  }
  const bool has_markers = mesh.boundary_marker.size() > 0;
  std::string face =
      fmt::format("# written by palpa\n{} {}\n", mesh.boundary.rows(), has_markers ? 1 : 0);
  for (Eigen::Index b = 0; b < mesh.boundary.rows(); ++b) {
    fmt::format_to(std::back_inserter(face), "{} {} {} {}", b + 1, mesh.boundary(b, 0) + 1,
                   mesh.boundary(b, 1) + 1, mesh.boundary(b, 2) + 1);
    if (has_markers) fmt::format_to(std::back_inserter(face), " {}", mesh.boundary_marker[b]);
    face += '\n';
  }
  OutputBatch batch;
  batch.add(stem.string() + ".node") << node;
  batch.add(stem.string() + ".ele") << ele;
  batch.add(stem.string() + ".face") << face;
  batch.commit();
}

}  // namespace palpa
