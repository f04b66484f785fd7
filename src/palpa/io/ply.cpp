// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/ply.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/binary.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::ByteOrder;
using io_detail::LineCursor;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PlyType> ply_type(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  return std::nullopt;
}

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 8;
}

struct Property {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  // lists only
  PlyType type = PlyType::Float32;      // the scalar, or the list items
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;

  const Property* find(std::string_view n) const {
    for (const auto& p : properties) {
      if (p.name == n) return &p;
    }
    return nullptr;
  }
  // Bytes of one item in a binary body if every list were empty.
  std::size_t min_bytes() const {
    std::size_t n = 0;
    for (const auto& p : properties) n += type_size(p.is_list ? p.count_type : p.type);
    return n;
  }
};

struct Header {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<Element> elements;
  LineCursor cursor;  // just after end_header
};

Header parse_header(const std::string& bytes, const std::string& file) {
  Header h{PlyEncoding::Ascii, {}, LineCursor(bytes, file)};
  LineCursor& cur = h.cursor;
  std::string_view line;
  if (!cur.next(line) || trim(line) != "ply") {
    cur.fail("not a PLY file: the first line is not 'ply'", "a file starting with the line ply");
  }
  bool have_format = false;
  while (cur.next(line)) {
    const auto tokens = split_whitespace(line);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (tokens.size() != 3) cur.fail("malformed format line", "format <encoding> 1.0");
      if (tokens[1] == "ascii") {
        h.encoding = PlyEncoding::Ascii;
      } else if (tokens[1] == "binary_little_endian") {
        h.encoding = PlyEncoding::BinaryLittleEndian;
      } else if (tokens[1] == "binary_big_endian") {
        h.encoding = PlyEncoding::BinaryBigEndian;
      } else {
        cur.fail(fmt::format("unknown PLY format '{}'", tokens[1]),
                 "ascii, binary_little_endian or binary_big_endian");
      }
      have_format = true;
    } else if (key == "element") {
      if (tokens.size() != 3) cur.fail("malformed element line", "element <name> <count>");
      const auto count = parse_integer(tokens[2]);
      if (!count || *count < 0) {
        cur.fail(fmt::format("element count '{}' is not a non-negative integer", tokens[2]));
      }
      h.elements.push_back({std::string(tokens[1]), *count, {}});
    } else if (key == "property") {
      if (h.elements.empty()) cur.fail("property before any element line");
      Property p;
      std::optional<PlyType> t;
      if (tokens.size() == 5 && tokens[1] == "list") {
        p.is_list = true;
        const auto ct = ply_type(tokens[2]);
        t = ply_type(tokens[3]);
        if (!ct || !t) {
          cur.fail(fmt::format("unknown type in '{}'", trim(line)),
                   "char, uchar, short, ushort, int, uint, float or double");
        }
        if (*ct == PlyType::Float32 || *ct == PlyType::Float64) {
          cur.fail("a list count must have an integer type");
        }
        p.count_type = *ct;
        p.name = tokens[4];
      } else if (tokens.size() == 3) {
        t = ply_type(tokens[1]);
        if (!t) {
          cur.fail(fmt::format("unknown type '{}'", tokens[1]),
                   "char, uchar, short, ushort, int, uint, float or double");
        }
        p.name = tokens[2];
      } else {
        cur.fail("malformed property line",
                 "property <type> <name> or property list <count type> <type> <name>");
      }
      p.type = *t;
      h.elements.back().properties.push_back(std::move(p));
    } else if (key == "end_header") {
      if (!have_format) cur.fail("the header has no format line", "format ascii 1.0 (or binary)");
      return h;
    } else {
      cur.fail(fmt::format("unexpected header line '{}'", trim(line).substr(0, 40)),
               "format, element, property, comment or end_header");
    }
  }
  cur.fail("the header has no end_header line");
}

// Reads element values one after another from an ascii or binary body, and
// names the current element in errors.
class Body {
 public:
  Body(const std::string& bytes, Header& header, std::string file, std::string promise)
      : bytes_(bytes),
        encoding_(header.encoding),
        cursor_(header.cursor),
        pos_(header.cursor.offset()),
        file_(std::move(file)),
        promise_(std::move(promise)) {}

  bool binary() const { return encoding_ != PlyEncoding::Ascii; }
  std::size_t remaining() const { return bytes_.size() - std::min(pos_, bytes_.size()); }

  void begin(const Element& e, long long index) {
    place_ = fmt::format("{}[{}]", e.name, index);
    if (binary()) return;
    std::string_view line;
    if (!cursor_.next_content(line, '\0')) {
      ErrorContext ctx;
      ctx.file = file_;
      ctx.line = cursor_.line_number();
      ctx.field = place_;
      throw_input_error(
          fmt::format("the file ends before {} (the header promises {})", place_, promise_), ctx);
    }
    tokens_ = split_whitespace(line);
    next_token_ = 0;
  }

  void end() {
    if (!binary() && next_token_ != tokens_.size()) {
      fail(fmt::format("{} values on the line, the header describes {}", tokens_.size(),
                       next_token_));
    }
  }

  double scalar(PlyType t, std::string_view what) {
    if (!binary()) {
      const std::string_view tok = token(what);
      if (t == PlyType::Float32 || t == PlyType::Float64) {
        return io_detail::parse_number(tok, cursor_, field(what));
      }
      return static_cast<double>(io_detail::parse_int(tok, cursor_, field(what)));
    }
    const std::size_t n = type_size(t);
    if (remaining() < n) {
      fail(
          fmt::format("truncated: the file ends at byte {} (property '{}'), but the header "
                      "promises {}",
                      bytes_.size(), what, promise_));
    }
    const char* p = bytes_.data() + pos_;
    pos_ += n;
    const ByteOrder order =
        encoding_ == PlyEncoding::BinaryLittleEndian ? ByteOrder::Little : ByteOrder::Big;
    switch (t) {
      case PlyType::Int8:
        return io_detail::load<std::int8_t>(p, order);
      case PlyType::UInt8:
        return io_detail::load<std::uint8_t>(p, order);
      case PlyType::Int16:
        return io_detail::load<std::int16_t>(p, order);
      case PlyType::UInt16:
        return io_detail::load<std::uint16_t>(p, order);
      case PlyType::Int32:
        return io_detail::load<std::int32_t>(p, order);
      case PlyType::UInt32:
        return io_detail::load<std::uint32_t>(p, order);
      case PlyType::Float32:
        return static_cast<double>(io_detail::load<float>(p, order));
      case PlyType::Float64:
        return io_detail::load<double>(p, order);
    }
    return 0.0;
  }

  long long integer(PlyType t, std::string_view what) {
    const double v = scalar(t, what);
    if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 9.0e15) {
      fail(fmt::format("property '{}' is {}, not an integer", what, v));
    }
    return static_cast<long long>(v);
  }

  [[noreturn]] void fail(const std::string& problem, const std::string& expected = {}) const {
    ErrorContext ctx;
    ctx.file = file_;
    if (!binary()) ctx.line = cursor_.line_number();
    ctx.field = place_;
    throw_input_error(problem, ctx, expected);
  }

 private:
  std::string field(std::string_view what) const { return fmt::format("{} {}", place_, what); }

  std::string_view token(std::string_view what) {
    if (next_token_ >= tokens_.size()) {
      fail(fmt::format("the line ends before property '{}'", what),
           "one line per element with every property of the header");
    }
    return tokens_[next_token_++];
  }

  const std::string& bytes_;
  PlyEncoding encoding_;
  LineCursor cursor_;
  std::size_t pos_;
  std::string file_;
  std::string promise_;
  std::string place_;
  std::vector<std::string_view> tokens_;
  std::size_t next_token_ = 0;
};

std::string describe_promise(const std::vector<Element>& elements) {
  std::string out;
  for (const auto& e : elements) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{} {}", e.count, e.name);
  }
  return out;
}

bool is_axis(std::string_view name) {
  return name == "x" || name == "y" || name == "z";
}

}  // namespace

PlyContents read_ply_with_scalars(const std::filesystem::path& path,
                                  const MeshReadOptions& options) {
  const std::string file = path.string();
  const std::string bytes = io_detail::read_file_bytes(path);
  Header header = parse_header(bytes, file);

  ErrorContext ctx;
  ctx.file = file;
  const Element* vertex_element = nullptr;
  for (const auto& e : header.elements) {
    if (e.name != "vertex") continue;
    if (vertex_element != nullptr) throw_input_error("two 'vertex' elements in the header", ctx);
    vertex_element = &e;
  }
  if (vertex_element == nullptr) {
    throw_input_error("the header declares no 'vertex' element", ctx,
                      "element vertex <count> with properties x, y, z");
  }
  for (const char* axis : {"x", "y", "z"}) {
    const Property* p = vertex_element->find(axis);
    if (p == nullptr || p->is_list) {
      throw_input_error(fmt::format("element 'vertex' has no scalar property '{}'", axis), ctx,
                        "property float x, y and z (any scalar type)");
    }
  }
  const long long vertex_count = vertex_element->count;
  if (vertex_count > io_detail::kMaxIndex) {
    throw_input_error(fmt::format("{} vertices are too many for 32-bit indices", vertex_count),
                      ctx);
  }

  Body body(bytes, header, file, describe_promise(header.elements));
  PlyContents out;
  std::vector<double> xyz;
  std::vector<std::vector<double>> extra;
  std::vector<io_detail::Triangle> triangles;
  std::vector<int> poly;
  bool faces_seen = false;

  for (const Element& e : header.elements) {
    // Reserve no more than the body can hold, whatever the header claims.
    const std::size_t unit = std::max<std::size_t>(body.binary() ? e.min_bytes() : 2, 1);
    const auto plausible = static_cast<std::size_t>(
        std::min<long long>(e.count, static_cast<long long>(body.remaining() / unit) + 1));
    if (e.name == "vertex") {
      xyz.reserve(3 * plausible);
      for (const auto& p : e.properties) {
        if (!p.is_list && !is_axis(p.name)) {
          out.vertex_scalars.push_back({p.name, {}});
          extra.emplace_back();
          extra.back().reserve(plausible);
        }
      }
      for (long long i = 0; i < e.count; ++i) {
        body.begin(e, i);
        double c[3] = {0.0, 0.0, 0.0};
        std::size_t k = 0;
        for (const auto& p : e.properties) {
          if (p.is_list) {
            const long long n = body.integer(p.count_type, p.name);
            for (long long j = 0; j < n; ++j) body.scalar(p.type, p.name);
            continue;
          }
          const double v = body.scalar(p.type, p.name);
          if (is_axis(p.name)) {
            if (!std::isfinite(v)) {
              body.fail(fmt::format("coordinate {} is {}", p.name, v), "a finite number");
            }
            c[p.name[0] - 'x'] = v;
          } else {
            extra[k++].push_back(v);
          }
        }
        body.end();
        xyz.insert(xyz.end(), {c[0], c[1], c[2]});
      }
    } else if (e.name == "face") {
      faces_seen = true;
      const Property* list = e.find("vertex_indices");
      if (list == nullptr) list = e.find("vertex_index");
      if (list == nullptr || !list->is_list) {
        throw_input_error("element 'face' has no list property 'vertex_indices'", ctx,
                          "property list uchar int vertex_indices");
      }
      triangles.reserve(plausible);
      for (long long i = 0; i < e.count; ++i) {
        body.begin(e, i);
        for (const auto& p : e.properties) {
          if (!p.is_list) {
            body.scalar(p.type, p.name);
            continue;
          }
          const long long n = body.integer(p.count_type, p.name);
          if (&p != list) {
            for (long long j = 0; j < n; ++j) body.scalar(p.type, p.name);
            continue;
          }
          if (n < 3) body.fail(fmt::format("face with {} corners", n), "at least 3 vertex indices");
          poly.clear();
          for (long long j = 0; j < n; ++j) {
            const long long index = body.integer(p.type, p.name);
            if (index < 0 || index >= vertex_count) {
              body.fail(fmt::format("vertex index {} is out of range: the file has {} vertices",
                                    index, vertex_count),
                        fmt::format("an index from 0 to {}", vertex_count - 1));
            }
            poly.push_back(static_cast<int>(index));
          }
          io_detail::fan_triangulate(poly, triangles);
        }
        body.end();
      }
    } else {
      for (long long i = 0; i < e.count; ++i) {
        body.begin(e, i);
        for (const auto& p : e.properties) {
          const long long n = p.is_list ? body.integer(p.count_type, p.name) : 1;
          for (long long j = 0; j < n; ++j) body.scalar(p.type, p.name);
        }
        body.end();
      }
    }
  }

  if (triangles.empty()) {
    throw_input_error(faces_seen ? "the mesh has no faces (element 'face' is empty)"
                                 : "the mesh has no faces (no 'face' element)",
                      ctx, "a mesh needs faces");
  }
  out.mesh.V = io_detail::positions_from(xyz);
  out.mesh.F = io_detail::triangles_from(triangles);
  io_detail::apply_unit(out.mesh.V, options, file);
  for (std::size_t k = 0; k < extra.size(); ++k) {
    out.vertex_scalars[k].values = Eigen::Map<const Eigen::VectorXd>(
        extra[k].data(), static_cast<Eigen::Index>(extra[k].size()));
  }
  return out;
}

SurfaceMesh read_ply(const std::filesystem::path& path, const MeshReadOptions& options) {
  return read_ply_with_scalars(path, options).mesh;
}

void write_ply(const std::filesystem::path& path, const SurfaceMesh& mesh,
               const PlyWriteOptions& options) {
  const Eigen::Index nv = mesh.V.rows();
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
  for (const auto& s : options.vertex_scalars) {
    if (s.values.size() == nv) io_detail::require_finite(s.values, path.string(), "vertex scalar '" + s.name + "'", "vertex");
  }
  for (std::size_t k = 0; k < options.vertex_scalars.size(); ++k) {
    const auto& s = options.vertex_scalars[k];
    const bool bad_name =
        s.name.empty() || is_axis(s.name) || s.name.find_first_of(" \t\r\n") != std::string::npos;
    bool duplicate = false;
    for (std::size_t j = 0; j < k; ++j)
      duplicate = duplicate || options.vertex_scalars[j].name == s.name;
    if (bad_name || duplicate || s.values.size() != nv) {
      throw Error(ErrorKind::Internal,
                  fmt::format("vertex property '{}' ({} values for {} vertices) cannot be written",
                              s.name, s.values.size(), nv),
                  ErrorContext{path.string(), 0, 0, {}});
    }
  }

  std::string out = "ply\n";
  switch (options.encoding) {
    case PlyEncoding::Ascii:
      out += "format ascii 1.0\n";
      break;
    case PlyEncoding::BinaryLittleEndian:
      out += "format binary_little_endian 1.0\n";
      break;
    case PlyEncoding::BinaryBigEndian:
      out += "format binary_big_endian 1.0\n";
      break;
  }
  out += "comment written by palpa\n";
  fmt::format_to(std::back_inserter(out),
                 "element vertex {}\nproperty double x\nproperty double y\nproperty double z\n",
                 nv);
  for (const auto& s : options.vertex_scalars) {
    fmt::format_to(std::back_inserter(out), "property double {}\n", s.name);
  }
  fmt::format_to(std::back_inserter(out),
                 "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                 mesh.F.rows());

  if (options.encoding == PlyEncoding::Ascii) {
    for (Eigen::Index i = 0; i < nv; ++i) {
      fmt::format_to(std::back_inserter(out), "{} {} {}", mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2));
      for (const auto& s : options.vertex_scalars)
        fmt::format_to(std::back_inserter(out), " {}", s.values[i]);
      out += '\n';
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      fmt::format_to(std::back_inserter(out), "3 {} {} {}\n", mesh.F(f, 0), mesh.F(f, 1),
                     mesh.F(f, 2));
    }
  } else {
    const ByteOrder order =
        options.encoding == PlyEncoding::BinaryLittleEndian ? ByteOrder::Little : ByteOrder::Big;
    const std::size_t vertex_bytes = 8 * (3 + options.vertex_scalars.size());
    out.reserve(out.size() + static_cast<std::size_t>(nv) * vertex_bytes +
                static_cast<std::size_t>(mesh.F.rows()) * 13);
    for (Eigen::Index i = 0; i < nv; ++i) {
      for (int c = 0; c < 3; ++c) io_detail::store<double>(out, mesh.V(i, c), order);
      for (const auto& s : options.vertex_scalars)
        io_detail::store<double>(out, s.values[i], order);
    }
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      io_detail::store<std::uint8_t>(out, 3, order);
      for (int c = 0; c < 3; ++c) io_detail::store<std::int32_t>(out, mesh.F(f, c), order);
    }
  }
  write_file_atomic(
      path, [&](std::ostream& s) { s.write(out.data(), static_cast<std::streamsize>(out.size())); },
      /*binary=*/true);
}

}  // namespace palpa
