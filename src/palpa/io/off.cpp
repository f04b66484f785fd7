// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/off.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "palpa/core/atomic_file.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

constexpr std::array<std::string_view, 8> kHeaders = {"OFF",   "COFF",   "NOFF",   "CNOFF",
                                                      "STOFF", "STCOFF", "STNOFF", "STCNOFF"};

}  // namespace

SurfaceMesh read_off(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  const std::string bytes = io_detail::read_file_bytes(path);
  io_detail::require_content(bytes, file);
  io_detail::LineCursor cursor(bytes, file);
  std::string_view line;

  cursor.next_content(line);
  auto tokens = io_detail::tokens_of(line);
  if (tokens.empty() || std::find(kHeaders.begin(), kHeaders.end(), tokens[0]) == kHeaders.end()) {
    cursor.fail(fmt::format("not an OFF file: the first line is '{}'", line.substr(0, 40)),
                "a first line OFF");
  }
  tokens.erase(tokens.begin());
  if (tokens.empty()) {
    if (!cursor.next_content(line)) cursor.fail("the file ends before the counts", "#V #F #E");
    tokens = io_detail::tokens_of(line);
  }
  if (tokens.size() < 2) cursor.fail("malformed counts line", "#vertices #faces #edges");
  const long long nv = io_detail::parse_int(tokens[0], cursor, "vertex count");
  const long long nf = io_detail::parse_int(tokens[1], cursor, "face count");
  if (nv < 0 || nf < 0 || nv > io_detail::kMaxIndex || nf > io_detail::kMaxIndex) {
    cursor.fail(fmt::format("invalid counts {} vertices, {} faces", nv, nf));
  }
  const auto limit = static_cast<long long>(bytes.size() / 2 + 1);  // no reserve past the file

  std::vector<double> xyz;
  xyz.reserve(static_cast<std::size_t>(3 * std::min(nv, limit)));
  for (long long i = 0; i < nv; ++i) {
    if (!cursor.next_content(line)) {
      cursor.fail(fmt::format("the file ends after {} of {} vertices", i, nv));
    }
    tokens = io_detail::tokens_of(line);
    if (tokens.size() < 3) {
      cursor.fail_field(fmt::format("vertex {}", i), fmt::format("{} coordinates", tokens.size()),
                        "x y z");
    }
    for (std::size_t c = 0; c < 3; ++c) {
      xyz.push_back(
          io_detail::parse_number(tokens[c], cursor, fmt::format("vertex {} {}", i, io_detail::kAxisNames[c])));
    }
  }
  std::vector<io_detail::Triangle> tris;
  tris.reserve(static_cast<std::size_t>(std::min(nf, limit)));
  std::vector<int> poly;
  for (long long f = 0; f < nf; ++f) {
    if (!cursor.next_content(line)) {
      cursor.fail(fmt::format("the file ends after {} of {} faces", f, nf));
    }
    tokens = io_detail::tokens_of(line);
    const std::string field = fmt::format("face {}", f);
    const long long n = io_detail::parse_int(tokens.front(), cursor, field + " corner count");
    if (n < 3) cursor.fail_field(field, fmt::format("{} corners", n), "at least 3");
    if (static_cast<long long>(tokens.size()) < n + 1) {
      cursor.fail_field(field, fmt::format("{} indices for {} corners", tokens.size() - 1, n));
    }
    poly.clear();
    for (long long k = 0; k < n; ++k) {
      const long long index =
          io_detail::parse_int(tokens[static_cast<std::size_t>(k + 1)], cursor, field + " index");
      if (index < 0 || index >= nv) {
        cursor.fail_field(
            field,
            fmt::format("vertex index {} is out of range: the file has {} vertices", index, nv),
            fmt::format("an index from 0 to {}", nv - 1));
      }
      poly.push_back(static_cast<int>(index));
    }
    io_detail::fan_triangulate(poly, tris);
  }
  if (tris.empty()) {
    ErrorContext ctx;
    ctx.file = file;
    throw_input_error("the mesh has no faces", ctx, "a mesh needs faces");
  }
  SurfaceMesh mesh;
  mesh.V = io_detail::positions_from(xyz);
  mesh.F = io_detail::triangles_from(tris);
  io_detail::apply_unit(mesh.V, options, file);
  return mesh;
}

void write_off(const std::filesystem::path& path, const SurfaceMesh& mesh) {
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
  std::string text = fmt::format("OFF\n{} {} 0\n", mesh.V.rows(), mesh.F.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    fmt::format_to(std::back_inserter(text), "{} {} {}\n", mesh.V(i, 0), mesh.V(i, 1),
                   mesh.V(i, 2));
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    fmt::format_to(std::back_inserter(text), "3 {} {} {}\n", mesh.F(f, 0), mesh.F(f, 1),
                   mesh.F(f, 2));
  }
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

}  // namespace palpa
