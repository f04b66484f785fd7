// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/obstacle.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "palpa/contact/detail/cgal_checks.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/closest_point_on_triangle.hpp"
#include "palpa/geometry/triangle_tree.hpp"

namespace palpa::contact {

namespace {

// Triangles with an area below this fraction of the squared bounding-box
// diagonal are degenerate; a volume below this fraction of its cube is zero.
constexpr double kDegenerateFraction = 1e-12;
constexpr double kRotationTolerance = 1e-9;
// Self-intersection search stops after this many pairs.
constexpr std::size_t kMaxReportedIntersections = 100;
// Triangles per task when the normals are recomputed.
constexpr std::size_t kNormalsGrain = 2048;

[[noreturn]] void fail(const std::string& name, const std::string& what,
                       const std::string& expected) {
  ErrorContext context;
  context.file = name;
  throw_input_error(what, context, expected);
}

void check_finite(const Eigen::MatrixX3d& V, const std::string& name) {
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!V.row(i).allFinite()) {
      fail(name,
           fmt::format("vertex {} has a non-finite coordinate ({}, {}, {})", i, V(i, 0), V(i, 1),
                       V(i, 2)),
           "finite vertex coordinates");
    }
  }
}

double bbox_diagonal(const Eigen::MatrixX3d& V) {
  return V.rows() == 0 ? 0.0 : (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

// One directed triangle side, keyed by its undirected edge.
struct Side {
  int lo, hi;  // vertex indices, lo < hi
  int face;
  int local;     // 0: v0→v1, 1: v1→v2, 2: v2→v0
  bool forward;  // runs lo → hi
};

// Checks closedness, manifoldness and consistent orientation; returns, per
// triangle side (3·f + local), the triangle across it.
std::vector<int> edge_neighbours(const Eigen::MatrixX3i& F, const std::string& name) {
  std::vector<Side> sides;
  sides.reserve(3 * static_cast<std::size_t>(F.rows()));
  for (int f = 0; f < static_cast<int>(F.rows()); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k);
      const int b = F(f, (k + 1) % 3);
      sides.push_back({std::min(a, b), std::max(a, b), f, k, a < b});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return std::tie(x.lo, x.hi, x.face) < std::tie(y.lo, y.hi, y.face);
  });
  std::vector<int> neighbour(sides.size(), -1);
  std::size_t boundary = 0;
  std::size_t nonmanifold = 0;
  std::size_t misoriented = 0;
  std::string boundary_example;
  std::string nonmanifold_example;
  std::string misoriented_example;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].lo == sides[i].lo && sides[j].hi == sides[i].hi) ++j;
    const Side& s = sides[i];
    if (j - i == 1) {
      if (boundary++ == 0) {
        boundary_example = fmt::format(
            "the edge between vertices {} and {}, used by triangle {} only", s.lo, s.hi, s.face);
      }
    } else if (j - i > 2) {
      if (nonmanifold++ == 0) {
        nonmanifold_example = fmt::format(
            "the edge between vertices {} and {} is shared by {} triangles", s.lo, s.hi, j - i);
      }
    } else if (sides[i].forward == sides[i + 1].forward) {
      if (misoriented++ == 0) {
        misoriented_example =
            fmt::format("triangles {} and {} both run from vertex {} to {}", s.face,
                        sides[i + 1].face, s.forward ? s.lo : s.hi, s.forward ? s.hi : s.lo);
      }
    } else {
      neighbour[3 * static_cast<std::size_t>(s.face) + static_cast<std::size_t>(s.local)] =
          sides[i + 1].face;
      neighbour[3 * static_cast<std::size_t>(sides[i + 1].face) +
                static_cast<std::size_t>(sides[i + 1].local)] = s.face;
    }
    i = j;
  }
  if (boundary > 0) {
    fail(name,
         fmt::format("the surface is not closed: {} boundary edge(s), e.g. {}", boundary,
                     boundary_example),
         "a closed triangle surface: every edge shared by exactly two triangles");
  }
  if (nonmanifold > 0) {
    fail(name,
         fmt::format(
             "the surface is not manifold: {} edge(s) shared by more than two triangles, e.g. {}",
             nonmanifold, nonmanifold_example),
         "every edge shared by exactly two triangles");
  }
  if (misoriented > 0) {
    fail(name,
         fmt::format(
             "inconsistent orientation: {} edge(s) where the two triangles disagree, e.g. {}",
             misoriented, misoriented_example),
         "consistently oriented triangles: each edge run once in each direction");
  }
  return neighbour;
}

void check_triangles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                     const std::string& name) {
  if (F.rows() == 0) fail(name, "the mesh has no triangles", "a closed triangle surface");
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (F(f, k) < 0 || F(f, k) >= V.rows()) {
        fail(name,
             fmt::format("triangle {} refers to vertex {}, but there are {} vertices", f, F(f, k),
                         V.rows()),
             "vertex indices in [0, #vertices)");
      }
    }
  }
  const double min_area = kDegenerateFraction * std::pow(bbox_diagonal(V), 2);
  std::size_t degenerate = 0;
  std::string example;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0));
    const double area =
        0.5 * (V.row(F(f, 1)).transpose() - a).cross(V.row(F(f, 2)).transpose() - a).norm();
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2) || !(area > min_area)) {
      if (degenerate++ == 0) {
        example = fmt::format("triangle {} (vertices {}, {}, {}) has area {:.3g} m²", f, F(f, 0),
                              F(f, 1), F(f, 2), area);
      }
    }
  }
  if (degenerate > 0) {
    fail(name, fmt::format("{} degenerate triangle(s), e.g. {}", degenerate, example),
         fmt::format("three distinct vertices and an area above {:.3g} m²", min_area));
  }
}

double enclosed_volume(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  double six_v = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    six_v += V.row(F(f, 0)).dot(V.row(F(f, 1)).cross(V.row(F(f, 2))));
  }
  return six_v / 6.0;
}

}  // namespace

struct Obstacle::Impl {
  std::string name;
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  bool flipped = false;
  double volume = 0.0;
  Pose pose;
  geometry::TriangleTree tree;               // in body coordinates
  std::vector<int> neighbour;                // 3·f + local side → triangle across
  std::vector<Eigen::Vector3d> face_normal;  // unit
  std::vector<int> corner_start;             // #V + 1: corners of vertex v are
  std::vector<int> corners;                  //   corners[corner_start[v] …), as 3·f + k

  Eigen::Vector3d corner(int f, int k) const { return V.row(F(f, k)); }

  // Unit face normals (in parallel). Edge and vertex pseudo-normals are
  // computed from them when a query needs one: a deforming obstacle pays only
  // for the face normals and the box refit.
  void update_normals() {
    const auto nf = static_cast<std::size_t>(F.rows());
    face_normal.resize(nf);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, kNormalsGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t f = r.begin(); f != r.end(); ++f) {
                          const int fi = static_cast<int>(f);
                          const Eigen::Vector3d n =
                              (corner(fi, 1) - corner(fi, 0)).cross(corner(fi, 2) - corner(fi, 0));
                          const double len = n.norm();
                          face_normal[f] =
                              len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
                        }
                      });
  }

  // Triangle corners around each vertex (CSR), for vertex pseudo-normals.
  void build_vertex_corners() {
    corner_start.assign(static_cast<std::size_t>(V.rows()) + 1, 0);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) ++corner_start[static_cast<std::size_t>(F(f, k)) + 1];
    }
    std::partial_sum(corner_start.begin(), corner_start.end(), corner_start.begin());
    corners.resize(static_cast<std::size_t>(3 * F.rows()));
    std::vector<int> fill(corner_start.begin(), corner_start.end() - 1);
    for (int f = 0; f < static_cast<int>(F.rows()); ++f) {
      for (int k = 0; k < 3; ++k)
        corners[static_cast<std::size_t>(fill[static_cast<std::size_t>(F(f, k))]++)] = 3 * f + k;
    }
  }

  // Sum of the two face normals across side `local` of triangle f.
  Eigen::Vector3d edge_pseudo_normal(int f, int local) const {
    const auto s = 3 * static_cast<std::size_t>(f) + static_cast<std::size_t>(local);
    return face_normal[static_cast<std::size_t>(f)] +
           face_normal[static_cast<std::size_t>(neighbour[s])];
  }

  // Σ corner angle × face normal over the triangles around vertex v.
  Eigen::Vector3d vertex_pseudo_normal(int v) const {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (int c = corner_start[static_cast<std::size_t>(v)];
         c < corner_start[static_cast<std::size_t>(v) + 1]; ++c) {
      const int f = corners[static_cast<std::size_t>(c)] / 3;
      const int k = corners[static_cast<std::size_t>(c)] % 3;
      const Eigen::Vector3d e1 = corner(f, (k + 1) % 3) - corner(f, k);
      const Eigen::Vector3d e2 = corner(f, (k + 2) % 3) - corner(f, k);
      n += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * face_normal[static_cast<std::size_t>(f)];
    }
    return n;
  }

  void build_tree(bool refit) {
    if (refit) {
      tree.refit(V);
    } else {
      tree.build(V, F);
    }
  }

  // Closest point to a body-coordinate point xb, in body coordinates.
  ClosestPoint closest_body(const Eigen::Vector3d& xb) const {
    const geometry::TriangleTree::Hit hit = tree.closest(xb);
    const int f = hit.triangle;
    const geometry::TrianglePoint& tp = hit.where;
    ClosestPoint out;
    out.point = tp.point;
    out.triangle = f;
    const Eigen::Vector3d d = xb - tp.point;
    out.distance = d.norm();
    const auto fs = static_cast<std::size_t>(f);
    Eigen::Vector3d normal;
    if (tp.region == geometry::kFace) {
      out.feature = Feature::Face;
      out.vertices = {F(f, 0), F(f, 1), F(f, 2)};
      out.weights = tp.weights;
      normal = face_normal[fs];
    } else if (tp.region >= geometry::kEdgeAB) {
      const int k = tp.region - geometry::kEdgeAB;
      const int a = F(f, k);
      const int b = F(f, (k + 1) % 3);
      const double wa = tp.weights[k];
      const double wb = tp.weights[(k + 1) % 3];
      out.feature = Feature::Edge;
      out.vertices = a < b ? std::array<int, 3>{a, b, -1} : std::array<int, 3>{b, a, -1};
      out.weights = a < b ? Eigen::Vector3d(wa, wb, 0.0) : Eigen::Vector3d(wb, wa, 0.0);
      normal = edge_pseudo_normal(f, k);
    } else {
      const int v = F(f, tp.region);
      out.feature = Feature::Vertex;
      out.vertices = {v, -1, -1};
      out.weights = {1.0, 0.0, 0.0};
      normal = vertex_pseudo_normal(v);
    }
    out.inside = d.dot(normal) < 0.0;
    return out;
  }

  ClosestPoint to_world(ClosestPoint c) const {
    c.point = pose.R * c.point + pose.t;
    return c;
  }
  Eigen::Vector3d to_body(const Eigen::Vector3d& x) const {
    return pose.R.transpose() * (x - pose.t);
  }
};

Obstacle::Obstacle(const SurfaceMesh& mesh, std::string name, const ObstacleOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.name = std::move(name);
  check_finite(mesh.V, m.name);
  check_triangles(mesh.V, mesh.F, m.name);
  m.V = mesh.V;
  m.F = mesh.F;
  m.neighbour = edge_neighbours(m.F, m.name);
  m.volume = enclosed_volume(m.V, m.F);
  const double min_volume = kDegenerateFraction * std::pow(bbox_diagonal(m.V), 3);
  if (std::abs(m.volume) <= min_volume) {
    fail(m.name, fmt::format("the surface encloses no volume ({:.3g} m³)", m.volume),
         "a closed surface around a solid");
  }
  if (m.volume < 0.0) {
    if (!options.flip_inward) {
      fail(m.name,
           fmt::format("the triangles are oriented inwards (enclosed volume {:.3g} m³ < 0)",
                       m.volume),
           "normals (v1−v0)×(v2−v0) pointing out of the solid");
    }
    m.F.col(1).swap(m.F.col(2));
    m.volume = -m.volume;
    m.flipped = true;
    m.neighbour = edge_neighbours(m.F, m.name);
  }
  if (options.check_self_intersections) {
    const detail::SelfIntersections crossing =
        detail::self_intersections(m.V, m.F, kMaxReportedIntersections);
    if (crossing.pairs > 0) {
      fail(m.name,
           fmt::format("the surface intersects itself: {}{} pair(s) of triangles cross, e.g. "
                       "triangles {} and {}",
                       crossing.pairs >= kMaxReportedIntersections ? "at least " : "",
                       crossing.pairs, crossing.first, crossing.second),
           "a surface that does not cross itself");
    }
  }
  m.build_vertex_corners();
  m.update_normals();
  m.build_tree(false);
}

Obstacle::Obstacle(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Obstacle::~Obstacle() = default;
Obstacle::Obstacle(Obstacle&&) noexcept = default;
Obstacle& Obstacle::operator=(Obstacle&&) noexcept = default;

const std::string& Obstacle::name() const {
  return impl_->name;
}
const Eigen::MatrixX3d& Obstacle::vertices() const {
  return impl_->V;
}
const Eigen::MatrixX3i& Obstacle::triangles() const {
  return impl_->F;
}
bool Obstacle::flipped() const {
  return impl_->flipped;
}
double Obstacle::volume() const {
  return impl_->volume;
}
const Pose& Obstacle::pose() const {
  return impl_->pose;
}

void Obstacle::set_pose(const Pose& pose) {
  const double err =
      (pose.R.transpose() * pose.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!pose.R.allFinite() || err > kRotationTolerance || pose.R.determinant() < 0.0) {
    fail(impl_->name, "the pose's R is not a rotation",
         "an orthonormal 3×3 matrix with determinant +1");
  }
  if (!pose.t.allFinite())
    fail(impl_->name, "the pose's translation is not finite", "finite coordinates [m]");
  impl_->pose = pose;
}

Eigen::Vector3d Obstacle::world_vertex(int i) const {
  return impl_->pose.R * impl_->V.row(i).transpose() + impl_->pose.t;
}

Obstacle Obstacle::deformed(const Eigen::MatrixX3d& body_vertices) const {
  Obstacle out(std::make_unique<Impl>(*impl_));
  out.set_vertices(body_vertices, true);
  return out;
}

void Obstacle::set_vertices(const Eigen::MatrixX3d& body_vertices, bool refit) {
  Impl& m = *impl_;
  if (body_vertices.rows() != m.V.rows()) {
    fail(m.name,
         fmt::format("{} new vertex positions for a mesh of {} vertices", body_vertices.rows(),
                     m.V.rows()),
         "one position per vertex");
  }
  check_finite(body_vertices, m.name);
  m.V = body_vertices;  // F keeps its (possibly flipped) winding
  m.update_normals();
  m.build_tree(refit);
}

ClosestPoint Obstacle::closest_point(const Eigen::Vector3d& x) const {
  return impl_->to_world(impl_->closest_body(impl_->to_body(x)));
}

bool Obstacle::penetration(const Eigen::Vector3d& x, ClosestPoint& out) const {
  const Eigen::Vector3d xb = impl_->to_body(x);
  if ((xb.array() < impl_->tree.lo().array()).any() ||
      (xb.array() > impl_->tree.hi().array()).any())
    return false;
  ClosestPoint c = impl_->closest_body(xb);
  if (!c.inside) return false;
  out = impl_->to_world(c);
  return true;
}

bool Obstacle::inside(const Eigen::Vector3d& x) const {
  ClosestPoint c;
  return penetration(x, c);
}

}  // namespace palpa::contact
