// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/io/gmsh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string_view>
#include <unordered_map>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/text.hpp"
#include "palpa/io/detail/binary.hpp"
#include "palpa/io/detail/mesh_build.hpp"
#include "palpa/io/detail/text_input.hpp"

namespace palpa {

namespace {

using io_detail::ByteOrder;
using io_detail::LineCursor;

constexpr int kTypeTriangle = 2;
constexpr int kTypeTetrahedron = 4;
constexpr int kMaxNodesPerElement = 8;
constexpr const char* kExportHint =
    "Gmsh format 4.1 or 2.2, ASCII or binary (in Gmsh: File > Export > .msh, 'Version 4 ASCII' "
    "or 'Version 4 Binary'; or gmsh -format msh41)";
constexpr const char* kLinearTypes =
    "linear elements: 4-node tetrahedra (type 4), 3-node triangles (2)";

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

using NodeTags = std::array<long long, kMaxNodesPerElement>;

enum class MshVersion { V41, V22 };

// The binary parts of a .msh file: fixed-size values in the file's byte order
// (size_t = 8 bytes, int = 4, double = 8). Every value and every count is
// checked against the bytes left before it is read or anything is reserved for
// it, so a truncated or damaged file is refused instead of read past its end.
// Errors name the section and the offset of the value they are about: the last
// value read, or where reading stopped after mark().
class MshBinary {
 public:
  MshBinary(std::string_view bytes, std::string file) : bytes_(bytes), file_(std::move(file)) {}

  void set_order(ByteOrder order) { order_ = order; }
  void begin(std::size_t offset, std::string section) {
    pos_ = offset;
    at_ = offset;
    section_ = std::move(section);
  }
  // Errors from now on name the current offset.
  void mark() { at_ = pos_; }
  std::size_t offset() const noexcept { return pos_; }
  std::size_t remaining() const noexcept { return bytes_.size() - std::min(pos_, bytes_.size()); }

  std::int32_t i32(const char* what) { return take<std::int32_t>(what); }
  std::uint64_t size(const char* what) { return take<std::uint64_t>(what); }
  double f64(const char* what) { return take<double>(what); }

  // `count` (just read) as a number of items of at least `item_bytes` bytes
  // each, refused unless they fit in the rest of the file (and in 32-bit
  // indices).
  long long fits(std::uint64_t count, std::uint64_t item_bytes, const std::string& items) const {
    const std::uint64_t room = remaining() / item_bytes;
    if (count > room) {
      fail(fmt::format("{} {} of {} bytes each do not fit in the {} bytes left in the file", count,
                       items, item_bytes, remaining()),
           fmt::format("at most {} {} (the file is truncated or a count is wrong)", room, items));
    }
    if (count > static_cast<std::uint64_t>(io_detail::kMaxIndex)) {
      fail(fmt::format("{} {} are too many for 32-bit indices", count, items));
    }
    return static_cast<long long>(count);
  }

  // Passes over `count` (just read) items of `item_bytes` bytes each.
  void skip(std::uint64_t count, std::uint64_t item_bytes, const std::string& items) {
    pos_ += static_cast<std::size_t>(static_cast<std::uint64_t>(fits(count, item_bytes, items)) *
                                     item_bytes);
  }
  // True when the next bytes close the section ("$End", perhaps after a line
  // end), where a block header is due: the header counted more blocks than
  // there are. (No block header starts so: as entity dimension or element
  // type, these bytes are out of range.)
  bool at_section_end() const {
    std::string_view rest = bytes_.substr(std::min(pos_, bytes_.size()));
    if (rest.starts_with("\r\n")) {
      rest.remove_prefix(2);
    } else if (rest.starts_with('\n')) {
      rest.remove_prefix(1);
    }
    return rest.starts_with("$End");
  }

  // Passes over `n` bytes of values that are not used.
  void skip_bytes(std::uint64_t n, const char* what) {
    at_ = pos_;
    if (remaining() < n) truncated(n, what);
    pos_ += static_cast<std::size_t>(n);
  }

  [[noreturn]] void fail(const std::string& problem, const std::string& expected = {}) const {
    fail_field({}, problem, expected);
  }
  [[noreturn]] void fail_field(const std::string& field, const std::string& problem,
                               const std::string& expected = {}) const {
    ErrorContext ctx;
    ctx.file = file_;
    ctx.field = fmt::format("{} at byte {}", section_, at_);
    if (!field.empty()) ctx.field += ", " + field;
    throw_input_error(problem, ctx, expected);
  }

 private:
  [[noreturn]] void truncated(std::uint64_t n, const char* what) const {
    fail(fmt::format("truncated: the file ends ({} bytes) inside the section, before {}",
                     bytes_.size(), what),
         fmt::format("{} more bytes for {}", n, what));
  }

  template <class T>
  T take(const char* what) {
    at_ = pos_;
    if (remaining() < sizeof(T)) truncated(sizeof(T), what);
    const T v = io_detail::load<T>(bytes_.data() + pos_, order_);
    pos_ += sizeof(T);
    return v;
  }

  std::string_view bytes_;
  std::string file_;
  ByteOrder order_ = ByteOrder::Little;
  std::size_t pos_ = 0;
  std::size_t at_ = 0;  // offset named by errors
  std::string section_;
};

// Reads the text with a line cursor; sections written in binary (binary files:
// the byte-order int, $Entities, $Nodes and $Elements after their count lines)
// are read with MshBinary, after which the line cursor moves past them.
class MshReader {
 public:
  MshReader(const std::string& bytes, std::string file)
      : cursor_(bytes, file), binary_(bytes, std::move(file)) {}

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
      if (name == "Entities" && version_ == MshVersion::V41) {
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

  // An error at the line being read, or at the byte within a binary section.
  [[noreturn]] void fail_field(const std::string& field, const std::string& problem,
                               const std::string& expected = {}) const {
    if (in_binary_) binary_.fail_field(field, problem, expected);
    cursor_.fail_field(field, problem, expected);
  }

  MshBinary& begin_binary(const char* section) {
    binary_.begin(cursor_.offset(), section);
    in_binary_ = true;
    return binary_;
  }

  void end_binary() {
    cursor_.skip_to(binary_.offset());
    in_binary_ = false;
    after_binary_ = true;
  }

  void expect_end(const std::string& name) {
    std::string_view line;
    const std::string end = "$End" + name;
    if (!cursor_.next_content(line, '\0') || trim(line) != end) {
      const std::string problem =
          fmt::format("section ${} is not closed where its counts say it ends", name);
      if (after_binary_) {
        binary_.mark();
        binary_.fail(problem, end);
      }
      cursor_.fail(problem, end);
    }
    after_binary_ = false;
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
    if (t[0] == "4.1") {
      version_ = MshVersion::V41;
    } else if (t[0] == "2.2") {
      version_ = MshVersion::V22;
    } else {
      cursor_.fail(fmt::format("Gmsh format version {} is not supported", t[0]), kExportHint);
    }
    if (t[1] == "1") {
      binary_file_ = true;
    } else if (t[1] != "0") {
      cursor_.fail(fmt::format("file-type {} is neither 0 (ASCII) nor 1 (binary)", t[1]),
                   kExportHint);
    }
    if (binary_file_) {
      if (t[2] != "8") {
        cursor_.fail(fmt::format("binary data-size {} is not supported", t[2]),
                     "8 (8-byte size_t and double, as 64-bit Gmsh writes)");
      }
      read_byte_order();
    }
    expect_end("MeshFormat");
  }

  // The int 1 written in binary after the format line tells the byte order.
  void read_byte_order() {
    MshBinary& b = begin_binary("$MeshFormat");
    b.set_order(ByteOrder::Little);
    const std::int32_t one = b.i32("the binary int 1");
    if (one == 0x01000000) {
      b.set_order(ByteOrder::Big);
    } else if (one != 1) {
      b.fail(fmt::format("the binary int after the format line is {}, not 1 in either byte order",
                         one),
             "the int 1 in 4 bytes, then a line end");
    }
    end_binary();
  }

  void read_entities() {
    if (binary_file_) {
      read_entities_binary();
      return;
    }
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

  // 4.1 binary: numPoints numCurves numSurfaces numVolumes (size_t); per point
  // tag (int), x y z (double), numPhysicalTags (size_t), tags (int); per
  // curve, surface, volume tag, a bounding box of 6 doubles, the physical tags
  // as for points, numBounding (size_t) and the bounding tags (int).
  void read_entities_binary() {
    MshBinary& b = begin_binary("$Entities");
    std::array<std::uint64_t, 4> n{};
    n[0] = b.size("numPoints");
    n[1] = b.size("numCurves");
    n[2] = b.size("numSurfaces");
    n[3] = b.size("numVolumes");
    for (std::size_t dim = 0; dim < 4; ++dim) {
      const std::uint64_t coordinates = dim == 0 ? 3 : 6;
      const std::uint64_t least = 4 + 8 * coordinates + 8 + (dim == 0 ? 0 : 8);
      const long long entities =
          b.fits(n[dim], least, fmt::format("entities of dimension {}", dim));
      for (long long e = 0; e < entities; ++e) {
        const long long tag = b.i32("the entity tag");
        b.skip_bytes(8 * coordinates, "the entity's coordinates");
        const long long physicals = b.fits(b.size("numPhysicalTags"), 4, "physical tags");
        int physical = 0;
        for (long long k = 0; k < physicals; ++k) {
          const std::int32_t v = b.i32("a physical tag");
          if (k == 0) physical = v;
        }
        if (dim > 0) b.skip(b.size("the number of bounding entities"), 4, "bounding entity tags");
        physical_[dim][tag] = physical;
      }
    }
    end_binary();
  }

  void add_node(long long tag, const std::array<double, 3>& p) {
    const auto [it, inserted] = node_index_.try_emplace(tag, static_cast<int>(xyz_.size() / 3));
    if (!inserted) fail_field(fmt::format("node {}", tag), "duplicate node tag");
    xyz_.insert(xyz_.end(), p.begin(), p.end());
  }

  // A binary coordinate; NaN and Inf are refused as in text.
  double coordinate(MshBinary& b, long long tag, std::size_t axis) {
    const double v = b.f64("a node coordinate");
    if (!std::isfinite(v)) {
      b.fail_field(fmt::format("node {} {}", tag, io_detail::kAxisNames[axis]),
                   fmt::format("{} is not a finite number", v), "a finite number");
    }
    return v;
  }

  // A size_t tag as a signed value.
  long long tag_of(std::uint64_t v, const char* what) const {
    if (v > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) {
      fail_field(what, fmt::format("{} is out of range", v));
    }
    return static_cast<long long>(v);
  }

  void reserve_nodes(long long n) {
    xyz_.reserve(xyz_.size() + 3 * static_cast<std::size_t>(n));
    node_index_.reserve(node_index_.size() + static_cast<std::size_t>(n));
  }

  void read_nodes() {
    if (have_nodes_) cursor_.fail("a second $Nodes section");
    have_nodes_ = true;
    if (version_ == MshVersion::V22) {
      read_nodes_22();
      return;
    }
    if (binary_file_) {
      read_nodes_binary();
      return;
    }
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
        std::array<double, 3> p{};
        for (std::size_t c = 0; c < 3; ++c) {
          p[c] = io_detail::parse_number(t[c], cursor_,
                                         fmt::format("node {} {}", tag, io_detail::kAxisNames[c]));
        }
        add_node(tag, p);
      }
      read += static_cast<std::size_t>(n);
    }
    if (read != static_cast<std::size_t>(total)) {
      cursor_.fail(
          fmt::format("the node blocks hold {} nodes, the $Nodes header says {}", read, total));
    }
  }

  // 4.1 binary: numEntityBlocks numNodes minNodeTag maxNodeTag (size_t); per
  // block entityDim entityTag parametric (int), numNodesInBlock (size_t), the
  // node tags (size_t), then per node x y z and, if parametric, entityDim
  // parametric coordinates (double).
  void read_nodes_binary() {
    MshBinary& b = begin_binary("$Nodes");
    const std::uint64_t blocks = b.size("numEntityBlocks");
    const std::uint64_t total = b.size("numNodes");
    b.size("minNodeTag");
    b.size("maxNodeTag");
    b.fits(blocks, 20, "node blocks");
    reserve_nodes(b.fits(total, 32, "nodes"));
    std::uint64_t read = 0;
    std::vector<long long> tags;
    for (std::uint64_t k = 0; k < blocks; ++k) {
      if (b.at_section_end()) {
        b.mark();
        b.fail(fmt::format("the $Nodes header counts {} node blocks, but the section ends after {}",
                           blocks, k));
      }
      const std::int32_t dim = b.i32("entityDim");
      b.i32("entityTag");
      const std::int32_t parametric = b.i32("parametric");
      if (parametric != 0 && parametric != 1) {
        b.fail_field("parametric", fmt::format("{} is neither 0 nor 1", parametric));
      }
      if (parametric == 1 && (dim < 0 || dim > 3)) {
        b.fail_field("entity dimension", fmt::format("{}", dim), "0 to 3");
      }
      const std::uint64_t extra = parametric == 1 ? static_cast<std::uint64_t>(dim) : 0;
      const long long n = b.fits(b.size("numNodesInBlock"), 8 * (1 + 3 + extra), "nodes");
      tags.resize(static_cast<std::size_t>(n));
      for (auto& tag : tags) tag = tag_of(b.size("a node tag"), "node tag");
      for (const long long tag : tags) {
        std::array<double, 3> p{};
        for (std::size_t c = 0; c < 3; ++c) p[c] = coordinate(b, tag, c);
        b.skip_bytes(8 * extra, "parametric coordinates");
        add_node(tag, p);
      }
      read += static_cast<std::uint64_t>(n);
    }
    if (read != total) {
      b.mark();
      b.fail(fmt::format("the node blocks hold {} nodes, the $Nodes header says {}", read, total));
    }
    end_binary();
  }

  // 2.2: number-of-nodes, then per node node-number x y z (in binary: int and
  // three doubles).
  void read_nodes_22() {
    const long long n = count(tokens(1, "number-of-nodes")[0], "number of nodes");
    if (!binary_file_) {
      for (long long i = 0; i < n; ++i) {
        const auto t = tokens(4, "node-number x y z");
        const long long tag = io_detail::parse_int(t[0], cursor_, "node number");
        std::array<double, 3> p{};
        for (std::size_t c = 0; c < 3; ++c) {
          p[c] = io_detail::parse_number(t[c + 1], cursor_,
                                         fmt::format("node {} {}", tag, io_detail::kAxisNames[c]));
        }
        add_node(tag, p);
      }
      return;
    }
    MshBinary& b = begin_binary("$Nodes");
    reserve_nodes(b.fits(static_cast<std::uint64_t>(n), 4 + 3 * 8, "nodes"));
    for (long long i = 0; i < n; ++i) {
      const long long tag = b.i32("a node number");
      std::array<double, 3> p{};
      for (std::size_t c = 0; c < 3; ++c) p[c] = coordinate(b, tag, c);
      add_node(tag, p);
    }
    end_binary();
  }

  int node(long long tag, long long element_tag) const {
    const auto it = node_index_.find(tag);
    if (it == node_index_.end()) {
      fail_field(fmt::format("element {}", element_tag),
                 fmt::format("node {} is not in $Nodes", tag));
    }
    return it->second;
  }

  int physical_of(std::size_t dim, long long entity) {
    const auto it = physical_[dim].find(entity);
    return it == physical_[dim].end() ? 0 : it->second;
  }

  // Nodes per element of `type`; refuses the types palpa does not know.
  int supported_nodes(long long type) const {
    const int per = nodes_per_element(type);
    if (per == 0) {
      fail_field("element type",
                 fmt::format("element type {} is not supported (second-order or unknown)", type),
                 kLinearTypes);
    }
    return per;
  }

  // Tets and triangles are kept (with `label`); other cells only have their
  // nodes checked.
  void add_element(long long type, long long tag, int label, const NodeTags& nodes) {
    if (type == kTypeTetrahedron) {
      Cell<4> c{tag, {}, label};
      for (std::size_t k = 0; k < 4; ++k) c.nodes[k] = node(nodes[k], tag);
      tets_.push_back(c);
      any_region_ = any_region_ || label != 0;
    } else if (type == kTypeTriangle) {
      Cell<3> c{tag, {}, label};
      for (std::size_t k = 0; k < 3; ++k) c.nodes[k] = node(nodes[k], tag);
      triangles_.push_back(c);
      any_marker_ = any_marker_ || label != 0;
    } else {
      const int per = nodes_per_element(type);
      for (int k = 0; k < per; ++k) node(nodes[static_cast<std::size_t>(k)], tag);
    }
  }

  void read_elements() {
    if (!have_nodes_) cursor_.fail("$Elements comes before $Nodes", "$Nodes first");
    if (version_ == MshVersion::V22) {
      read_elements_22();
      return;
    }
    if (binary_file_) {
      read_elements_binary();
      return;
    }
    const auto h = tokens(4, "numEntityBlocks numElements minElementTag maxElementTag");
    const long long blocks = count(h[0], "number of element blocks");
    const long long total = count(h[1], "number of elements");
    long long read = 0;
    NodeTags nodes{};
    for (long long b = 0; b < blocks; ++b) {
      const auto bh = tokens(4, "entityDim entityTag elementType numElementsInBlock");
      const long long dim = io_detail::parse_int(bh[0], cursor_, "entity dimension");
      const long long entity = io_detail::parse_int(bh[1], cursor_, "entity tag");
      const long long type = io_detail::parse_int(bh[2], cursor_, "element type");
      const long long n = count(bh[3], "number of elements in block");
      const int per = supported_nodes(type);
      if (dim < 0 || dim > 3) cursor_.fail_field("entity dimension", fmt::format("{}", dim));
      const int label = physical_of(static_cast<std::size_t>(dim), entity);
      for (long long i = 0; i < n; ++i) {
        const auto t = tokens(static_cast<std::size_t>(1 + per), "elementTag nodeTag...");
        const long long tag = io_detail::parse_int(t[0], cursor_, "element tag");
        for (std::size_t k = 0; k < static_cast<std::size_t>(per); ++k) {
          nodes[k] = io_detail::parse_int(t[k + 1], cursor_, "node tag");
        }
        add_element(type, tag, label, nodes);
      }
      read += n;
    }
    if (read != total) {
      cursor_.fail(fmt::format("the element blocks hold {} elements, the $Elements header says {}", read, total));
    }
  }

  // 4.1 binary: numEntityBlocks numElements minElementTag maxElementTag
  // (size_t); per block entityDim entityTag elementType (int),
  // numElementsInBlock (size_t), then per element its tag and node tags (size_t).
  void read_elements_binary() {
    MshBinary& b = begin_binary("$Elements");
    const std::uint64_t blocks = b.size("numEntityBlocks");
    const std::uint64_t total = b.size("numElements");
    b.size("minElementTag");
    b.size("maxElementTag");
    b.fits(blocks, 20, "element blocks");
    NodeTags nodes{};
    std::uint64_t read = 0;
    for (std::uint64_t k = 0; k < blocks; ++k) {
      if (b.at_section_end()) {
        b.mark();
        b.fail(fmt::format(
            "the $Elements header counts {} element blocks, but the section ends after {}", blocks,
            k));
      }
      const std::int32_t dim = b.i32("entityDim");
      const std::int32_t entity = b.i32("entityTag");
      const std::int32_t type = b.i32("elementType");
      const int per = supported_nodes(type);
      const std::uint64_t in_block = b.size("numElementsInBlock");
      if (dim < 0 || dim > 3) b.fail_field("entity dimension", fmt::format("{}", dim), "0 to 3");
      const int label = physical_of(static_cast<std::size_t>(dim), entity);
      const long long n = b.fits(in_block, 8 * (1 + static_cast<std::uint64_t>(per)), "elements");
      for (long long i = 0; i < n; ++i) {
        const long long tag = tag_of(b.size("an element tag"), "element tag");
        for (std::size_t j = 0; j < static_cast<std::size_t>(per); ++j) {
          nodes[j] = tag_of(b.size("a node tag"), "node tag");
        }
        add_element(type, tag, label, nodes);
      }
      read += static_cast<std::uint64_t>(n);
    }
    if (read != total) {
      b.mark();
      b.fail(fmt::format("the element blocks hold {} elements, the $Elements header says {}", read, total));
    }
    end_binary();
  }

  // 2.2: number-of-elements, then per element elm-number elm-type
  // number-of-tags tags... node-numbers...; the first tag is the physical
  // group. In binary the elements come in blocks: elm-type,
  // number-of-elements-in-block, number-of-tags (int), then per element
  // elm-number, the tags and the node numbers (int).
  void read_elements_22() {
    const long long total = count(tokens(1, "number-of-elements")[0], "number of elements");
    NodeTags nodes{};
    if (!binary_file_) {
      for (long long i = 0; i < total; ++i) {
        const char* expected = "elm-number elm-type number-of-tags tags... node-numbers...";
        const auto t = tokens(3, expected);
        const long long tag = io_detail::parse_int(t[0], cursor_, "element number");
        const long long type = io_detail::parse_int(t[1], cursor_, "element type");
        const auto ntags = static_cast<std::size_t>(count(t[2], "number of tags"));
        const int per = supported_nodes(type);
        const std::size_t needed = 3 + ntags + static_cast<std::size_t>(per);
        if (t.size() < needed) {
          cursor_.fail(fmt::format("{} values on the line, the element needs {}", t.size(), needed),
                       expected);
        }
        const int label =
            ntags > 0 ? static_cast<int>(io_detail::parse_int(t[3], cursor_, "physical tag")) : 0;
        for (std::size_t k = 0; k < static_cast<std::size_t>(per); ++k) {
          nodes[k] = io_detail::parse_int(t[3 + ntags + k], cursor_, "node number");
        }
        add_element(type, tag, label, nodes);
      }
      return;
    }
    MshBinary& b = begin_binary("$Elements");
    long long read = 0;
    while (read < total) {
      if (b.at_section_end()) {
        b.mark();
        b.fail(fmt::format("the $Elements header counts {} elements, but the section ends after {}",
                           total, read));
      }
      const std::int32_t type = b.i32("elm-type");
      const int per = supported_nodes(type);
      const std::int32_t in_block = b.i32("number-of-elements-in-block");
      if (in_block < 0 || in_block > total - read) {
        b.fail_field("number-of-elements-in-block",
                     fmt::format("{} elements in the block, but {} of the header's {} are left",
                                 in_block, total - read, total));
      }
      const std::int32_t ntags = b.i32("number-of-tags");
      if (ntags < 0) b.fail_field("number-of-tags", fmt::format("{} is out of range", ntags));
      const std::uint64_t ints =
          1 + static_cast<std::uint64_t>(ntags) + static_cast<std::uint64_t>(per);
      const long long n = b.fits(static_cast<std::uint64_t>(in_block), 4 * ints, "elements");
      for (long long i = 0; i < n; ++i) {
        const long long tag = b.i32("an element number");
        int label = 0;
        for (std::int32_t k = 0; k < ntags; ++k) {
          const std::int32_t v = b.i32("a tag");
          if (k == 0) label = v;
        }
        for (std::size_t j = 0; j < static_cast<std::size_t>(per); ++j) {
          nodes[j] = b.i32("a node number");
        }
        add_element(type, tag, label, nodes);
      }
      read += n;
    }
    end_binary();
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
  MshBinary binary_;
  MshVersion version_ = MshVersion::V41;
  bool binary_file_ = false;
  bool in_binary_ = false;     // reading a binary part: errors name the byte
  bool after_binary_ = false;  // the section's data was binary
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
  io_detail::require_finite(mesh.V, path.string(), "vertex positions", "vertex");
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
