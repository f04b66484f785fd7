// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/vtu.hpp"

#include <fmt/format.h>

#include <cassert>
#include <cmath>
#include <optional>
#include <set>

#include <zlib.h>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/base64.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/binary.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"
#include "palpa/io/detail/xml_scan.hpp"

namespace palpa {

namespace {

using io_detail::ByteOrder;
using io_detail::XmlScanner;
using io_detail::XmlTag;

constexpr const char* kFileVersion = "1.0";

[[noreturn]] void internal_error(const std::filesystem::path& path, const std::string& problem) {
  throw Error(ErrorKind::Internal, problem, ErrorContext{path.string(), 0, 0, {}});
}

std::optional<VtkCellType> cell_type_of(long long code) {
  switch (code) {
    case 1:
      return VtkCellType::Vertex;
    case 5:
      return VtkCellType::Triangle;
    case 9:
      return VtkCellType::Quad;
    case 10:
      return VtkCellType::Tetra;
    default:
      return std::nullopt;
  }
}

// ---- writing ---------------------------------------------------------------

// The appended block and the XML that points into it.
class AppendedWriter {
 public:
  // Adds a raw array (UInt64 byte count, then the bytes) and returns the XML
  // DataArray element for it.
  std::string add(const std::string& type, const std::string& name, Eigen::Index components,
                  const std::string& bytes) {
    const std::size_t offset = blob_.size();
    io_detail::store<std::uint64_t>(blob_, bytes.size(), ByteOrder::Little);
    blob_ += bytes;
    std::string xml =
        fmt::format(R"(<DataArray type="{}" Name="{}")", type, io_detail::xml_escape(name));
    if (components != 1) xml += fmt::format(R"( NumberOfComponents="{}")", components);
    xml += fmt::format(R"( format="appended" offset="{}"/>)", offset);
    return xml;
  }
  const std::string& blob() const { return blob_; }

 private:
  std::string blob_;
};

std::string float64_bytes(const Eigen::MatrixXd& values) {
  std::string bytes;
  bytes.reserve(static_cast<std::size_t>(values.size()) * 8);
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      io_detail::store<double>(bytes, values(r, c), ByteOrder::Little);
    }
  }
  return bytes;
}

void check_arrays(const std::filesystem::path& path, const std::vector<DataArray>& arrays,
                  Eigen::Index rows, const char* where) {
  std::set<std::string> names;
  for (const DataArray& a : arrays) {
    if (a.name.empty() || !names.insert(a.name).second) {
      internal_error(path, fmt::format("{} array name '{}' is empty or repeated", where, a.name));
    }
    if (a.values.rows() != rows || a.values.cols() < 1) {
      internal_error(path, fmt::format("{} array '{}' is {}×{}, the grid needs {} rows", where,
                                       a.name, a.values.rows(), a.values.cols(), rows));
    }
  }
}

// ---- reading ---------------------------------------------------------------

struct RawArray {
  std::string section;  // Points, Cells, PointData, CellData
  std::string name;
  std::string type;
  Eigen::Index components = 1;
  std::string format;
  std::size_t offset = 0;
  std::string text;  // inline content
  std::size_t line = 0;
};

std::size_t type_size(std::string_view t) {
  if (t == "Int8" || t == "UInt8") return 1;
  if (t == "Int16" || t == "UInt16") return 2;
  if (t == "Int32" || t == "UInt32" || t == "Float32") return 4;
  if (t == "Int64" || t == "UInt64" || t == "Float64") return 8;
  return 0;
}

double load_value(std::string_view t, const char* p, ByteOrder o) {
  if (t == "Int8") return io_detail::load<std::int8_t>(p, o);
  if (t == "UInt8") return io_detail::load<std::uint8_t>(p, o);
  if (t == "Int16") return io_detail::load<std::int16_t>(p, o);
  if (t == "UInt16") return io_detail::load<std::uint16_t>(p, o);
  if (t == "Int32") return io_detail::load<std::int32_t>(p, o);
  if (t == "UInt32") return io_detail::load<std::uint32_t>(p, o);
  if (t == "Int64") return static_cast<double>(io_detail::load<std::int64_t>(p, o));
  if (t == "UInt64") return static_cast<double>(io_detail::load<std::uint64_t>(p, o));
  if (t == "Float32") return static_cast<double>(io_detail::load<float>(p, o));
  return io_detail::load<double>(p, o);
}

class VtuReader {
 public:
  VtuReader(const std::string& bytes, std::string file) : bytes_(bytes), file_(std::move(file)) {}

  UnstructuredGrid read() {
    split_appended();
    scan_header();
    return assemble();
  }

 private:
  [[noreturn]] void fail(const RawArray& a, const std::string& problem,
                         const std::string& expected = {}) const {
    ErrorContext ctx;
    ctx.file = file_;
    ctx.line = a.line;
    ctx.field = fmt::format("DataArray '{}'", a.name);
    throw_input_error(problem, ctx, expected);
  }
  [[noreturn]] void fail_at(std::size_t line, const std::string& problem,
                            const std::string& expected = {}) const {
    ErrorContext ctx;
    ctx.file = file_;
    ctx.line = line;
    throw_input_error(problem, ctx, expected);
  }

  void split_appended() {
    const std::size_t at = bytes_.find("<AppendedData");
    xml_ = std::string_view(bytes_).substr(0, at);
    if (at == std::string::npos) return;
    const std::size_t close = bytes_.find('>', at);
    const std::size_t underscore = close == std::string::npos ? close : bytes_.find('_', close);
    if (underscore == std::string::npos) {
      fail_at(XmlScanner(bytes_, file_).line_of(at), "AppendedData has no '_' data marker");
    }
    const std::string_view tag = std::string_view(bytes_).substr(at, close - at);
    if (tag.find("raw") == std::string_view::npos) {
      fail_at(XmlScanner(bytes_, file_).line_of(at), "appended data is not raw",
              "AppendedData encoding=\"raw\" (or inline arrays)");
    }
    appended_ = underscore + 1;
  }

  void scan_header() {
    XmlScanner scanner(xml_, file_);
    XmlTag tag;
    std::string_view text;
    std::vector<std::string> stack;
    std::optional<RawArray> open_array;
    bool seen_root = false;
    while (scanner.next(tag, text)) {
      if (open_array && !stack.empty() && stack.back() == "DataArray") open_array->text += text;
      const std::size_t line = scanner.line_of(tag.begin);
      if (tag.closing) {
        if (stack.empty() || stack.back() != tag.name) {
          fail_at(line, fmt::format("</{}> does not close the open element", tag.name));
        }
        stack.pop_back();
        if (tag.name == "DataArray" && open_array) {
          arrays_.push_back(std::move(*open_array));
          open_array.reset();
        }
        continue;
      }
      if (!seen_root) {
        seen_root = true;
        read_root(tag, line);
      } else if (tag.name == "Piece") {
        if (++pieces_ > 1) {
          fail_at(line, "the file holds several pieces", "one Piece (merge the blocks first)");
        }
        number_of_points_ = count_attribute(tag, "NumberOfPoints", line);
        number_of_cells_ = count_attribute(tag, "NumberOfCells", line);
      } else if (tag.name == "DataArray" && !stack.empty()) {
        const std::string& parent = stack.back();
        if (parent == "Points" || parent == "Cells" || parent == "PointData" ||
            parent == "CellData") {
          RawArray a = describe(tag, parent, line);
          if (tag.self_closing) {
            arrays_.push_back(std::move(a));
          } else {
            open_array = std::move(a);
          }
        }
      }
      if (!tag.self_closing) stack.push_back(tag.name);
    }
    if (!seen_root) fail_at(1, "no XML elements: not a .vtu file", "a VTKFile element");
    if (pieces_ == 0) fail_at(1, "no Piece element", "an UnstructuredGrid with one Piece");
  }

  void read_root(const XmlTag& tag, std::size_t line) {
    const std::string* type = tag.attribute("type");
    if (tag.name != "VTKFile" || type == nullptr) {
      fail_at(line, fmt::format("not a VTK XML file: the root element is <{}>", tag.name),
              "<VTKFile type=\"UnstructuredGrid\">");
    }
    if (*type != "UnstructuredGrid") {
      fail_at(line, fmt::format("a {} file, not an UnstructuredGrid", *type),
              "a .vtu UnstructuredGrid");
    }
    if (const std::string* c = tag.attribute("compressor")) {
      if (*c != "vtkZLibDataCompressor") {
        fail_at(line, fmt::format("compressed data ({}) is not supported", *c),
                "zlib compression (vtkZLibDataCompressor, ParaView's and meshio's default) or none");
      }
      zlib_ = true;
    }
    if (const std::string* order = tag.attribute("byte_order")) {
      order_ = *order == "BigEndian" ? ByteOrder::Big : ByteOrder::Little;
    }
    if (const std::string* header = tag.attribute("header_type")) {
      if (*header != "UInt32" && *header != "UInt64") {
        fail_at(line, fmt::format("header_type {} is not supported", *header), "UInt32 or UInt64");
      }
      header_bytes_ = *header == "UInt64" ? 8 : 4;
    }
  }

  Eigen::Index count_attribute(const XmlTag& tag, const char* key, std::size_t line) const {
    const std::string* v = tag.attribute(key);
    const auto n = v != nullptr ? parse_integer(*v) : std::nullopt;
    if (!n || *n < 0 || *n > io_detail::kMaxIndex) {
      fail_at(line, fmt::format("<{}> has no valid {}", tag.name, key), "a non-negative integer");
    }
    return static_cast<Eigen::Index>(*n);
  }

  RawArray describe(const XmlTag& tag, const std::string& section, std::size_t line) const {
    RawArray a;
    a.section = section;
    a.line = line;
    if (const std::string* n = tag.attribute("Name")) a.name = *n;
    const std::string* type = tag.attribute("type");
    if (type == nullptr || type_size(*type) == 0) {
      fail(a, fmt::format("unknown data type '{}'", type != nullptr ? *type : std::string()),
           "Int8..Int64, UInt8..UInt64, Float32 or Float64");
    }
    a.type = *type;
    if (const std::string* c = tag.attribute("NumberOfComponents")) {
      const auto n = parse_integer(*c);
      if (!n || *n < 1 || *n > 64) fail(a, fmt::format("NumberOfComponents '{}' is invalid", *c));
      a.components = static_cast<Eigen::Index>(*n);
    }
    const std::string* format = tag.attribute("format");
    a.format = format != nullptr ? *format : "ascii";
    if (a.format == "appended") {
      const std::string* off = tag.attribute("offset");
      const auto n = off != nullptr ? parse_integer(*off) : std::nullopt;
      if (!n || *n < 0) fail(a, "appended array without a valid offset");
      a.offset = static_cast<std::size_t>(*n);
    } else if (a.format != "ascii" && a.format != "binary") {
      fail(a, fmt::format("unknown format '{}'", a.format), "ascii, binary or appended");
    }
    return a;
  }

  // Values of an array, row-major, as doubles; exactly `count` of them.
  std::vector<double> values(const RawArray& a, std::size_t count) const {
    std::vector<double> out;
    if (a.format == "ascii") {
      const auto tokens = split_whitespace(a.text);
      if (tokens.size() != count) {
        fail(a, fmt::format("{} values, expected {}", tokens.size(), count));
      }
      out.reserve(count);
      for (std::string_view t : tokens) {
        const auto v = parse_finite_double(t);
        if (!v) fail(a, io_detail::number_problem(t), "a finite number");
        out.push_back(*v);
      }
      return out;
    }
    std::string decoded;
    std::string_view block;
    if (a.format == "binary") {
      auto d = base64_decode(a.text);
      if (!d) fail(a, "inline binary data is not valid base64");
      decoded = std::move(*d);
      block = decoded;
    } else {
      if (appended_ == std::string::npos) fail(a, "appended array but no AppendedData section");
      const std::size_t start = appended_ + a.offset;
      if (start > bytes_.size()) {
        fail(a, fmt::format("truncated: offset {} is past the end of the appended data", a.offset));
      }
      block = std::string_view(bytes_).substr(start);
    }
    const std::size_t size = type_size(a.type);
    if (zlib_) {
      const std::string raw = inflate_blocks(a, block, static_cast<std::uint64_t>(count) * size);
      out.reserve(count);
      for (std::size_t i = 0; i < count; ++i) out.push_back(load_value(a.type, raw.data() + i * size, order_));
      return out;
    }
    if (block.size() < header_bytes_) {
      fail(a, "truncated: the array's byte count is missing");
    }
    const std::uint64_t n_bytes = header_bytes_ == 8
                                      ? io_detail::load<std::uint64_t>(block.data(), order_)
                                      : io_detail::load<std::uint32_t>(block.data(), order_);
    if (n_bytes > block.size() - header_bytes_) {
      fail(a, fmt::format("truncated: the array promises {} bytes, the file holds {}", n_bytes,
                          block.size() - header_bytes_));
    }
    if (n_bytes != static_cast<std::uint64_t>(count) * size) {
      fail(a, fmt::format("{} bytes of {}, expected {} values", n_bytes, a.type, count));
    }
    out.reserve(count);
    const char* p = block.data() + header_bytes_;
    for (std::size_t i = 0; i < count; ++i) out.push_back(load_value(a.type, p + i * size, order_));
    return out;
  }

  // The bytes of a zlib-compressed array: a header of header_type integers
  // (number of blocks, uncompressed block size, size of the last block or 0
  // when it is full, then each block's compressed size), then the blocks.
  // `expected` is known from the element counts, so nothing is allocated or
  // inflated beyond it.
  std::string inflate_blocks(const RawArray& a, std::string_view block, std::uint64_t expected) const {
    const auto word = [&](std::size_t i) -> std::uint64_t {
      const std::size_t at = i * header_bytes_;
      if (at + header_bytes_ > block.size()) fail(a, "truncated: the compression header is incomplete");
      return header_bytes_ == 8 ? io_detail::load<std::uint64_t>(block.data() + at, order_)
                                : io_detail::load<std::uint32_t>(block.data() + at, order_);
    };
    const std::uint64_t blocks = word(0);
    const std::uint64_t block_size = word(1);
    const std::uint64_t last = word(2);
    if (blocks == 0) {
      if (expected != 0) fail(a, fmt::format("no compressed blocks, expected {} bytes", expected));
      return {};
    }
    if (block_size == 0 || last > block_size || blocks > expected / block_size + 1) {
      fail(a, fmt::format("a compression header of {} blocks of {} bytes (last {}) cannot hold {} bytes", blocks,
                          block_size, last, expected));
    }
    const std::uint64_t total = (blocks - 1) * block_size + (last == 0 ? block_size : last);
    if (total != expected) {
      fail(a, fmt::format("{} bytes of {} once inflated, expected {}", total, a.type, expected));
    }
    std::size_t at = static_cast<std::size_t>((3 + blocks) * header_bytes_);
    if (at > block.size()) fail(a, "truncated: the compression header is incomplete");
    // Before anything is allocated: the blocks must be in the file, and hold
    // what they claim (zlib inflates at most 1032:1).
    std::uint64_t packed_total = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t packed = word(static_cast<std::size_t>(3 + b));
      if (packed > block.size() - at - packed_total) {
        fail(a, fmt::format("truncated: block {} promises {} compressed bytes, the file holds {}", b + 1, packed,
                            block.size() - at - packed_total));
      }
      packed_total += packed;
    }
    constexpr std::uint64_t kZlibMaxRatio = 1032;
    if (total / kZlibMaxRatio > packed_total) {
      fail(a, fmt::format("{} compressed bytes cannot inflate to the {} bytes the header claims", packed_total,
                          total));
    }
    std::string out(static_cast<std::size_t>(total), '\0');
    std::size_t written = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t packed = word(static_cast<std::size_t>(3 + b));
      const std::uint64_t want = b + 1 == blocks && last != 0 ? last : block_size;
      if (packed > block.size() - at) {
        fail(a, fmt::format("truncated: block {} promises {} compressed bytes, the file holds {}", b + 1, packed,
                            block.size() - at));
      }
      uLongf got = static_cast<uLongf>(want);
      const int rc = uncompress(reinterpret_cast<Bytef*>(out.data() + written), &got,
                                reinterpret_cast<const Bytef*>(block.data() + at), static_cast<uLong>(packed));
      if (rc != Z_OK || got != want) {
        fail(a, fmt::format("block {} of {} does not inflate to {} bytes ({})", b + 1, blocks, want,
                            rc == Z_OK ? fmt::format("{} bytes", got) : std::string(zError(rc))));
      }
      written += static_cast<std::size_t>(want);
      at += static_cast<std::size_t>(packed);
    }
    return out;
  }

  const RawArray& find(const std::string& section, const std::string& name) const {
    for (const RawArray& a : arrays_) {
      if (a.section == section && a.name == name) return a;
    }
    fail_at(1, fmt::format("no {} array '{}'", section, name), "a complete UnstructuredGrid");
  }

  Eigen::MatrixXd matrix(const RawArray& a, Eigen::Index rows) const {
    const auto v = values(a, static_cast<std::size_t>(rows * a.components));
    Eigen::MatrixXd m(rows, a.components);
    for (Eigen::Index r = 0; r < rows; ++r) {
      for (Eigen::Index c = 0; c < a.components; ++c) {
        m(r, c) = v[static_cast<std::size_t>(r * a.components + c)];
      }
    }
    return m;
  }

  UnstructuredGrid assemble() const {
    UnstructuredGrid grid;
    const Eigen::Index np = number_of_points_;
    const Eigen::Index nc = number_of_cells_;
    const RawArray* points = nullptr;
    for (const RawArray& a : arrays_) {
      if (a.section == "Points") points = &a;
    }
    if (points == nullptr) fail_at(1, "no Points array", "a complete UnstructuredGrid");
    if (points->components != 3) fail(*points, "points need 3 components");
    grid.points = matrix(*points, np);
    for (Eigen::Index i = 0; i < np; ++i) {
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(grid.points(i, c))) {
          fail(*points, fmt::format("point {} has a coordinate {}", i, grid.points(i, c)),
               "finite coordinates");
        }
      }
    }

    const RawArray& types_array = find("Cells", "types");
    const RawArray& offsets_array = find("Cells", "offsets");
    const RawArray& connectivity_array = find("Cells", "connectivity");
    const auto types = values(types_array, static_cast<std::size_t>(nc));
    const auto offsets = values(offsets_array, static_cast<std::size_t>(nc));
    const double total = nc > 0 ? offsets.back() : 0.0;
    if (total < 0.0 || total > static_cast<double>(bytes_.size())) {
      fail(offsets_array, fmt::format("last offset {} is not plausible for the file size", total));
    }
    const auto connectivity = values(connectivity_array, static_cast<std::size_t>(total));
    // First pass: check types and offsets, and size the runs of equal type.
    std::vector<std::pair<VtkCellType, Eigen::Index>> runs;
    double previous = 0.0;
    for (Eigen::Index c = 0; c < nc; ++c) {
      const auto ci = static_cast<std::size_t>(c);
      const auto type = cell_type_of(static_cast<long long>(types[ci]));
      if (!type) {
        fail(types_array,
             fmt::format("cell {} has VTK type {}, which palpa does not read", c, types[ci]),
             "vertex (1), triangle (5), quad (9) or tetra (10)");
      }
      const int size = vtk_cell_size(*type);
      if (offsets[ci] - previous != size) {
        fail(offsets_array, fmt::format("cell {} has {} corners, a VTK type {} cell has {}", c,
                                        offsets[ci] - previous, types[ci], size));
      }
      if (runs.empty() || runs.back().first != *type) runs.emplace_back(*type, 0);
      ++runs.back().second;
      previous = offsets[ci];
    }
    for (const auto& [type, rows] : runs) {
      grid.cells.push_back({type, Eigen::MatrixXi(rows, vtk_cell_size(type))});
    }
    // Second pass: the corners.
    std::size_t next = 0;
    std::size_t block_index = 0;
    Eigen::Index row = 0;
    for (Eigen::Index c = 0; c < nc; ++c) {
      CellBlock& block = grid.cells[block_index];
      for (Eigen::Index k = 0; k < block.nodes.cols(); ++k) {
        const double index = connectivity[next++];
        if (index < 0 || index >= static_cast<double>(np) || index != std::floor(index)) {
          fail(connectivity_array,
               fmt::format("cell {} refers to point {}, the grid has {} points", c, index, np),
               fmt::format("indices from 0 to {}", np - 1));
        }
        block.nodes(row, k) = static_cast<int>(index);
      }
      if (++row == block.nodes.rows()) {
        row = 0;
        ++block_index;
      }
    }
    for (const RawArray& a : arrays_) {
      if (a.section == "PointData") grid.point_data.push_back({a.name, matrix(a, np)});
      if (a.section == "CellData") grid.cell_data.push_back({a.name, matrix(a, nc)});
    }
    return grid;
  }

  const std::string& bytes_;
  std::string file_;
  std::string_view xml_;
  std::size_t appended_ = std::string::npos;
  ByteOrder order_ = ByteOrder::Little;
  std::size_t header_bytes_ = 4;
  bool zlib_ = false;
  int pieces_ = 0;
  Eigen::Index number_of_points_ = 0;
  Eigen::Index number_of_cells_ = 0;
  std::vector<RawArray> arrays_;
};

}  // namespace

int vtk_cell_size(VtkCellType type) noexcept {
  switch (type) {
    case VtkCellType::Vertex:
      return 1;
    case VtkCellType::Triangle:
      return 3;
    case VtkCellType::Quad:
      return 4;
    case VtkCellType::Tetra:
      return 4;
  }
  return 0;
}

Eigen::Index UnstructuredGrid::cell_count() const noexcept {
  Eigen::Index n = 0;
  for (const CellBlock& b : cells) n += b.nodes.rows();
  return n;
}

const DataArray* UnstructuredGrid::find_point_data(const std::string& name) const noexcept {
  for (const DataArray& a : point_data) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

const DataArray* UnstructuredGrid::find_cell_data(const std::string& name) const noexcept {
  for (const DataArray& a : cell_data) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

Eigen::MatrixX3d embed_planar(const Eigen::MatrixX2d& rz) {
  Eigen::MatrixX3d p(rz.rows(), 3);
  p.leftCols<2>() = rz;
  p.col(2).setZero();
  return p;
}

UnstructuredGrid grid_of(const SurfaceMesh& mesh) {
  UnstructuredGrid grid;
  grid.points = mesh.V;
  grid.cells.push_back({VtkCellType::Triangle, mesh.F});
  return grid;
}

UnstructuredGrid grid_of(const TetMesh& mesh) {
  UnstructuredGrid grid;
  grid.points = mesh.V;
  grid.cells.push_back({VtkCellType::Tetra, mesh.T});
  if (mesh.region.size() > 0) grid.cell_data.push_back({"region", mesh.region.cast<double>()});
  return grid;
}

void write_vtu(const std::filesystem::path& path, const UnstructuredGrid& grid) {
  const Eigen::Index np = grid.points.rows();
  const Eigen::Index nc = grid.cell_count();
  for (const CellBlock& b : grid.cells) {
    if (b.nodes.cols() != vtk_cell_size(b.type)) {
      internal_error(path, fmt::format("a block of VTK type {} has {} corners per cell",
                                       static_cast<int>(b.type), b.nodes.cols()));
    }
    if (b.nodes.size() > 0 && (b.nodes.minCoeff() < 0 || b.nodes.maxCoeff() >= np)) {
      internal_error(path, fmt::format("a cell refers to a point outside 0..{}", np - 1));
    }
  }
  check_arrays(path, grid.point_data, np, "point data");
  check_arrays(path, grid.cell_data, nc, "cell data");
  io_detail::require_finite(grid.points, path.string(), "point positions", "point");
  for (const DataArray& a : grid.point_data) {
    io_detail::require_finite(a.values, path.string(), "point data '" + a.name + "'", "point");
  }
  for (const DataArray& a : grid.cell_data) {
    io_detail::require_finite(a.values, path.string(), "cell data '" + a.name + "'", "cell");
  }

  AppendedWriter appended;
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += fmt::format(
      "<VTKFile type=\"UnstructuredGrid\" version=\"{}\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n",
      kFileVersion);
  xml += "  <UnstructuredGrid>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", np, nc);
  const auto data_section = [&](const char* tag, const std::vector<DataArray>& arrays) {
    if (arrays.empty()) return;
    xml += fmt::format("      <{}>\n", tag);
    for (const DataArray& a : arrays) {
      xml += "        " +
             appended.add("Float64", a.name, a.values.cols(), float64_bytes(a.values)) + "\n";
    }
    xml += fmt::format("      </{}>\n", tag);
  };
  data_section("PointData", grid.point_data);
  data_section("CellData", grid.cell_data);

  xml += "      <Points>\n        ";
  xml += appended.add("Float64", "Points", 3, float64_bytes(grid.points));
  xml += "\n      </Points>\n";

  std::string connectivity;
  std::string offsets;
  std::string types;
  std::int64_t end = 0;
  for (const CellBlock& b : grid.cells) {
    for (Eigen::Index c = 0; c < b.nodes.rows(); ++c) {
      for (Eigen::Index k = 0; k < b.nodes.cols(); ++k) {
        io_detail::store<std::int64_t>(connectivity, b.nodes(c, k), ByteOrder::Little);
      }
      end += b.nodes.cols();
      io_detail::store<std::int64_t>(offsets, end, ByteOrder::Little);
      io_detail::store<std::uint8_t>(types, static_cast<std::uint8_t>(b.type), ByteOrder::Little);
    }
  }
  xml += "      <Cells>\n";
  xml += "        " + appended.add("Int64", "connectivity", 1, connectivity) + "\n";
  xml += "        " + appended.add("Int64", "offsets", 1, offsets) + "\n";
  xml += "        " + appended.add("UInt8", "types", 1, types) + "\n";
  xml += "      </Cells>\n";
  xml += "    </Piece>\n  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";
  write_file_atomic(
      path,
      [&](std::ostream& out) {
        out << xml;
        out.write(appended.blob().data(), static_cast<std::streamsize>(appended.blob().size()));
        out << "\n  </AppendedData>\n</VTKFile>\n";
      },
      /*binary=*/true);
}

UnstructuredGrid read_vtu(const std::filesystem::path& path) {
  const std::string bytes = io_detail::read_file_bytes(path);
  io_detail::require_content(bytes, path.string());
  return VtuReader(bytes, path.string()).read();
}

void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries) {
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  xml += "  <Collection>\n";
  for (const PvdEntry& e : entries) {
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time,
                       io_detail::xml_escape(e.file.generic_string()));
  }
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, [&](std::ostream& out) { out << xml; });
}

std::vector<PvdEntry> read_pvd(const std::filesystem::path& path) {
  const std::string bytes = io_detail::read_file_bytes(path);
  io_detail::require_content(bytes, path.string());
  XmlScanner scanner(bytes, path.string());
  XmlTag tag;
  std::string_view text;
  std::vector<PvdEntry> entries;
  bool collection = false;
  while (scanner.next(tag, text)) {
    if (tag.closing) continue;
    const std::size_t line = scanner.line_of(tag.begin);
    ErrorContext ctx;
    ctx.file = path.string();
    ctx.line = line;
    if (tag.name == "VTKFile") {
      const std::string* type = tag.attribute("type");
      if (type == nullptr || *type != "Collection") {
        throw_input_error("not a .pvd collection", ctx, "<VTKFile type=\"Collection\">");
      }
      collection = true;
    } else if (tag.name == "DataSet") {
      const std::string* time = tag.attribute("timestep");
      const std::string* file = tag.attribute("file");
      if (file == nullptr) throw_input_error("DataSet without a file attribute", ctx);
      PvdEntry e;
      e.file = *file;
      if (time != nullptr) {
        const auto t = parse_finite_double(*time);
        if (!t) {
          ctx.field = "timestep";
          throw_input_error(io_detail::number_problem(*time), ctx, "a finite number");
        }
        e.time = *t;
      }
      entries.push_back(std::move(e));
    }
  }
  if (!collection) {
    ErrorContext ctx;
    ctx.file = path.string();
    throw_input_error("not a .pvd collection", ctx, "<VTKFile type=\"Collection\">");
  }
  return entries;
}

PvdSeries::PvdSeries(std::filesystem::path pvd_path) : pvd_path_(std::move(pvd_path)) {}

std::filesystem::path PvdSeries::add(double time, const UnstructuredGrid& grid) {
  assert((entries_.empty() || time > entries_.back().time) && "PVD times must increase");
  const std::string name = fmt::format("{}_{:04}.vtu", pvd_path_.stem().string(), entries_.size());
  const std::filesystem::path vtu = pvd_path_.parent_path() / name;
  write_vtu(vtu, grid);
  entries_.push_back({time, name});
  write_pvd(pvd_path_, entries_);
  return vtu;
}

}  // namespace palpa
