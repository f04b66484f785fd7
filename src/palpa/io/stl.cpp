// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/stl.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/binary.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::ByteOrder;

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kPreambleBytes = 84;  // header + uint32 triangle count
constexpr std::size_t kTriangleBytes = 50;  // normal, 3 corners (12 float32), uint16
constexpr std::size_t kSniffBytes = 512;    // bytes looked at to tell ASCII from binary

using Point = std::array<double, 3>;

struct PointHash {
  std::size_t operator()(const Point& p) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (double c : p) {
      h ^= std::bit_cast<std::uint64_t>(c);
      h *= 1099511628211ull;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }
};

// Welds exactly equal corners into one vertex, numbered in order of first use.
class Welder {
 public:
  int add(Point p) {
    for (double& c : p) {
      if (c == 0.0) c = 0.0;  // -0 and +0 are the same point
    }
    const auto [it, inserted] = index_.try_emplace(p, static_cast<int>(xyz_.size() / 3));
    if (inserted) xyz_.insert(xyz_.end(), p.begin(), p.end());
    return it->second;
  }
  const std::vector<double>& xyz() const { return xyz_; }

 private:
  std::unordered_map<Point, int, PointHash> index_;
  std::vector<double> xyz_;
};

bool starts_with_solid(std::string_view bytes) {
  const std::string_view t = trim(bytes.substr(io_detail::bom_length(bytes), kHeaderBytes));
  return t.substr(0, 5) == "solid";
}

// ASCII STL is text: no NUL and no control characters besides white space.
bool looks_like_text(std::string_view bytes) {
  const std::string_view head = bytes.substr(0, kSniffBytes);
  for (const char ch : head) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == 0 || (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v')) {
      return false;
    }
  }
  return true;
}

SurfaceMesh read_binary(const std::string& bytes, const std::string& file) {
  ErrorContext ctx;
  ctx.file = file;
  if (bytes.size() < kPreambleBytes) {
    throw_input_error(fmt::format("truncated: {} bytes is shorter than the 84-byte binary STL "
                                  "header, and the file is not ASCII STL",
                                  bytes.size()),
                      ctx,
                      "binary STL (80-byte header, triangle count, 50 bytes per triangle) "
                      "or ASCII STL starting with 'solid'");
  }
  const auto count = io_detail::load<std::uint32_t>(bytes.data() + kHeaderBytes, ByteOrder::Little);
  const std::size_t expected = kPreambleBytes + kTriangleBytes * static_cast<std::size_t>(count);
  if (bytes.size() < expected) {
    const std::size_t complete = (bytes.size() - kPreambleBytes) / kTriangleBytes;
    ctx.field = fmt::format("triangle[{}]", complete);
    throw_input_error(fmt::format("truncated: the header promises {} triangles (84 + 50·{} = {} "
                                  "bytes), but the file has {} bytes",
                                  count, count, expected, bytes.size()),
                      ctx);
  }
  Welder welder;
  std::vector<io_detail::Triangle> tris;
  tris.reserve(count);
  for (std::size_t t = 0; t < count; ++t) {
    const char* p = bytes.data() + kPreambleBytes + kTriangleBytes * t + 12;  // skip the normal
    io_detail::Triangle tri{};
    for (int corner = 0; corner < 3; ++corner) {
      Point q{};
      for (int c = 0; c < 3; ++c) {
        const float v = io_detail::load<float>(p + 4 * (3 * corner + c), ByteOrder::Little);
        if (!std::isfinite(v)) {
          ctx.field = fmt::format("triangle[{}]", t);
          throw_input_error(fmt::format("corner {} has a coordinate {}", corner + 1, v), ctx,
                            "finite coordinates");
        }
        q[static_cast<std::size_t>(c)] = static_cast<double>(v);
      }
      tri[static_cast<std::size_t>(corner)] = welder.add(q);
    }
    tris.push_back(tri);
  }
  if (tris.empty()) {
    throw_input_error("the mesh has no faces (the binary STL holds 0 triangles)", ctx,
                      "a mesh needs faces");
  }
  SurfaceMesh mesh;
  mesh.V = io_detail::positions_from(welder.xyz());
  mesh.F = io_detail::triangles_from(tris);
  return mesh;
}

SurfaceMesh read_ascii(const std::string& bytes, const std::string& file) {
  io_detail::LineCursor cursor(bytes, file);
  Welder welder;
  std::vector<io_detail::Triangle> tris;
  std::vector<int> loop;
  enum class State { Outside, InSolid, InFacet, InLoop, LoopDone };
  State state = State::Outside;
  const char* expected_next = "solid";
  std::string_view line;
  const auto unexpected = [&](std::string_view key) {
    cursor.fail(fmt::format("unexpected '{}'", key), fmt::format("'{}'", expected_next));
  };
  while (cursor.next(line)) {
    const auto tokens = split_whitespace(line);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "solid") {
      if (state != State::Outside) unexpected(key);
      state = State::InSolid;
      expected_next = "facet normal";
    } else if (key == "endsolid") {
      if (state != State::InSolid) unexpected(key);
      state = State::Outside;
      expected_next = "solid";
    } else if (key == "facet") {
      if (state != State::InSolid) unexpected(key);
      state = State::InFacet;
      expected_next = "outer loop";
    } else if (key == "outer") {
      if (state != State::InFacet) unexpected(key);
      state = State::InLoop;
      loop.clear();
      expected_next = "vertex x y z";
    } else if (key == "vertex") {
      if (state != State::InLoop) unexpected(key);
      if (tokens.size() != 4) cursor.fail("a vertex line needs 3 coordinates", "vertex x y z");
      const int n = static_cast<int>(tris.size()) + 1;
      Point q{};
      for (std::size_t c = 0; c < 3; ++c) {
        q[c] = io_detail::parse_number(tokens[c + 1], cursor,
                                       fmt::format("facet {} vertex {}", n, loop.size() + 1));
      }
      loop.push_back(welder.add(q));
    } else if (key == "endloop") {
      if (state != State::InLoop) unexpected(key);
      if (loop.size() != 3) {
        cursor.fail(fmt::format("a facet with {} vertices", loop.size()), "3 vertices per facet");
      }
      tris.push_back({loop[0], loop[1], loop[2]});
      state = State::LoopDone;
      expected_next = "endfacet";
    } else if (key == "endfacet") {
      if (state != State::LoopDone) unexpected(key);
      state = State::InSolid;
      expected_next = "facet normal or endsolid";
    } else {
      cursor.fail(fmt::format("unexpected '{}' in ASCII STL", key.substr(0, 40)),
                  fmt::format("'{}'", expected_next));
    }
  }
  if (state != State::Outside && state != State::InSolid) {
    cursor.fail("the file ends inside a facet", fmt::format("'{}'", expected_next));
  }
  if (tris.empty()) {
    ErrorContext ctx;
    ctx.file = file;
    throw_input_error("the mesh has no faces (no facets)", ctx, "a mesh needs faces");
  }
  SurfaceMesh mesh;
  mesh.V = io_detail::positions_from(welder.xyz());
  mesh.F = io_detail::triangles_from(tris);
  return mesh;
}

}  // namespace

SurfaceMesh read_stl(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  const std::string bytes = io_detail::read_file_bytes(path);
  bool binary = true;
  if (bytes.size() >= kPreambleBytes) {
    const auto count =
        io_detail::load<std::uint32_t>(bytes.data() + kHeaderBytes, ByteOrder::Little);
    const bool size_fits =
        bytes.size() == kPreambleBytes + kTriangleBytes * static_cast<std::size_t>(count);
    // The size formula decides, unless the file is plainly ASCII STL text.
    binary = size_fits ? !(starts_with_solid(bytes) && looks_like_text(bytes.substr(kHeaderBytes)))
                       : !(starts_with_solid(bytes) && looks_like_text(bytes));
  } else {
    binary = !(starts_with_solid(bytes) && looks_like_text(bytes));
  }
  SurfaceMesh mesh = binary ? read_binary(bytes, file) : read_ascii(bytes, file);
  io_detail::apply_unit(mesh.V, options, file);
  return mesh;
}

void write_stl(const std::filesystem::path& path, const SurfaceMesh& mesh) {
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
  std::string out;
  out.reserve(kPreambleBytes + kTriangleBytes * static_cast<std::size_t>(mesh.F.rows()));
  std::string header = "binary STL written by palpa";
  header.resize(kHeaderBytes, ' ');
  out += header;
  io_detail::store<std::uint32_t>(out, static_cast<std::uint32_t>(mesh.F.rows()),
                                  ByteOrder::Little);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1));
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2));
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      io_detail::store<float>(out, static_cast<float>(n[k]), ByteOrder::Little);
    for (int corner = 0; corner < 3; ++corner) {
      for (int k = 0; k < 3; ++k) {
        io_detail::store<float>(out, static_cast<float>(mesh.V(mesh.F(f, corner), k)),
                                ByteOrder::Little);
      }
    }
    io_detail::store<std::uint16_t>(out, 0, ByteOrder::Little);
  }
  write_file_atomic(
      path, [&](std::ostream& s) { s.write(out.data(), static_cast<std::streamsize>(out.size())); },
      /*binary=*/true);
}

}  // namespace palpa
