// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/mesh/layer.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/closest_point.hpp"
#include "palpa/geometry/format.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"
#include "palpa/mesh/csg.hpp"
#include "palpa/mesh/detail/cgal_offset.hpp"
#include "palpa/mesh/detail/cgal_surface.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using geometry::format_point;

// Rays start this fraction of an edge inside the surface.
constexpr double kRayOffset = 1e-3;

std::string length(double v) { return format_quantity(v, Dimension::Length); }


// One point strictly inside each connected component of a closed surface.
std::vector<Eigen::Vector3d> inside_points(const SurfaceMesh& s, double edge) {
  // Components by union-find over triangles' vertices.
  std::vector<int> parent(static_cast<std::size_t>(s.V.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    parent[find(s.F(f, 0))] = find(s.F(f, 1));
    parent[find(s.F(f, 1))] = find(s.F(f, 2));
  }
  const detail::SurfaceQueries queries(s);
  const Eigen::MatrixX3d normals = geometry::face_normals(s);
  std::map<int, bool> done;
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    const int c = find(s.F(f, 0));
    if (done[c]) continue;
    const Eigen::Vector3d n = normals.row(f).transpose();
    if (n.isZero()) continue;
    const Eigen::Vector3d centre =
        (s.V.row(s.F(f, 0)) + s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))).transpose() / 3.0;
    const double delta = kRayOffset * edge;
    const auto hit = queries.ray_hit(centre - delta * n, -n, -1);
    if (!hit) continue;
    const Eigen::Vector3d p = centre - (delta + 0.5 * *hit) * n;
    if (!queries.inside(p)) continue;
    points.push_back(p);
    done[c] = true;
  }
  return points;
}

// The outward faces of tets seen by one tet only, ordered by their sorted
// vertex triples.
std::vector<std::array<int, 3>> boundary_faces(const TetMesh& tets) {
  const Eigen::MatrixX3i faces = geometry::boundary_of(tets).faces;
  std::vector<std::array<int, 3>> out(static_cast<std::size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    out[static_cast<std::size_t>(f)] = {faces(f, 0), faces(f, 1), faces(f, 2)};
  }
  const auto key = [](std::array<int, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  std::sort(out.begin(), out.end(), [&](const std::array<int, 3>& a, const std::array<int, 3>& b) {
    return key(a) < key(b);
  });
  return out;
}

// Per-outer-vertex depth: uniform or interpolated from samples.
Eigen::VectorXd depth_field(const SurfaceMesh& outer, const DepthSpec& spec,
                            const LayerOptions& options) {
  if (!spec.samples) {
    if (!(spec.uniform > 0.0) || !std::isfinite(spec.uniform)) {
      throw_input_error(fmt::format("layer depth {} is not positive", length(spec.uniform)), {},
                        "a depth > 0");
    }
    return Eigen::VectorXd::Constant(outer.V.rows(), spec.uniform);
  }
  const Samples& s = *spec.samples;
  for (Eigen::Index i = 0; i < s.values.size(); ++i) {
    if (!(s.values(i) > 0.0)) {
      throw_input_error(fmt::format("{} has depth {}", s.labels[i], length(s.values(i))),
                        in_file(s.source).with_field(s.field), "a depth > 0");
    }
  }
  geometry::InterpolationOptions io;
  io.method = options.interpolation;
  io.max_distance = options.max_sample_distance;
  io.source = s.source;
  io.sample_labels = s.labels;
  return geometry::SurfaceInterpolator(outer, s.positions, io).interpolate(s.values);
}

// Stiffness samples interpolated to the outer vertices [Pa].
Eigen::VectorXd stiffness_field(const SurfaceMesh& outer, const Samples& samples,
                                const LayerOptions& options) {
  // From a gel's to a hard plastic's: a value outside is a unit gone wrong
  // (a modulus written in kPa under a column in Pa, or the reverse).
  constexpr double kLowest = 1.0, kHighest = 1e9;
  for (Eigen::Index i = 0; i < samples.values.size(); ++i) {
    if (!(samples.values(i) >= kLowest && samples.values(i) <= kHighest)) {
      throw_input_error(fmt::format("{} has Young's modulus {}", samples.labels[i],
                                    format_quantity(samples.values(i), Dimension::Pressure)),
                        in_file(samples.source).with_field(samples.field), "a modulus from 1 Pa to 1 GPa");
    }
  }
  geometry::InterpolationOptions io;
  io.method = options.interpolation;
  io.max_distance = options.max_sample_distance;
  io.source = samples.source;
  io.sample_labels = samples.labels;
  return geometry::SurfaceInterpolator(outer, samples.positions, io).interpolate(samples.values);
}

// The core must stay at least this many edge lengths thick to be meshed.
constexpr double kMinCoreEdges = 2.0;

// The depth at p on face f of the outer surface, interpolated linearly from
// its corners' depths.
double depth_on_face(const SurfaceMesh& outer, const Eigen::VectorXd& depth, Eigen::Index f,
                     const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = outer.V.row(outer.F(f, 0)).transpose();
  const Eigen::Vector3d b = outer.V.row(outer.F(f, 1)).transpose();
  const Eigen::Vector3d c = outer.V.row(outer.F(f, 2)).transpose();
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (!(area2 > 0.0)) return depth(outer.F(f, 0));
  const double wa = (c - b).cross(p - b).dot(n) / area2;
  const double wb = (a - c).cross(p - c).dot(n) / area2;
  return wa * depth(outer.F(f, 0)) + wb * depth(outer.F(f, 1)) + (1.0 - wa - wb) * depth(outer.F(f, 2));
}

// Checks the depth against the local thickness; with `clamp`, thins the
// layer where it does not fit instead (to half of the thickness minus a core
// of one edge, as the far side is pushed in too; never below half an edge;
// eased over a few rings so the core has no step) and returns how many
// vertices were thinned.
Eigen::Index check_thickness(const SurfaceMesh& outer, const Eigen::MatrixX3d& normals,
                             Eigen::VectorXd& depth, double edge, bool clamp,
                             const std::string& source) {
  const detail::SurfaceQueries queries(outer);
  const double delta = kRayOffset * edge;
  const double core = kMinCoreEdges * edge;
  // Thinned spots may keep a core of one edge length and a layer of half one.
  const double thin_core = 1.0 * edge;
  const double thinnest = 0.5 * edge;
  Eigen::Index clamped = 0;
  for (Eigen::Index i = 0; i < outer.V.rows(); ++i) {
    const Eigen::Vector3d p = outer.V.row(i).transpose();
    const Eigen::Vector3d n = normals.row(i).transpose();
    const auto hit = queries.ray_hit(p - delta * n, -n, -1);
    const double thickness = hit ? delta + *hit : 0.0;
    // The skin where the inward normal leaves the body carries a layer of
    // its own, pushed toward this one: the two and the core share the room.
    double far = 0.0;
    if (hit) {
      const Eigen::Vector3d exit = p - thickness * n;
      far = depth_on_face(outer, depth, queries.closest(exit).first, exit);
    }
    // The core keeps two edges beside this layer, and one beside both.
    if (depth(i) + core <= thickness && depth(i) + far + thin_core <= thickness) continue;
    // Thinned, the layer may take half of what the core leaves: the skin
    // on the far side is pushed inward too.
    // Where even that is below the thinnest layer, the thinnest layer is
    // kept as long as the two sides' layers cannot meet (thickness above
    // two of them); the inner surface's own checks then have the last word,
    // since a ray along a normal that grazes a nearby slope underestimates
    // the room there.
    if (clamp && thickness >= 2.0 * thinnest) {
      depth(i) = std::min(depth(i), std::max(thinnest, 0.5 * (thickness - thin_core)));
      ++clamped;
      continue;
    }
    throw_input_error(
        clamp ? fmt::format("the layer at {} cannot be thinned to fit: the body is {} thick there along "
                            "the inward normal, less than two of the thinnest layers ({})",
                            format_point(p), length(thickness), length(thinnest))
              : fmt::format("the layer depth {} at {} does not fit: the body is {} thick there along "
                            "the inward normal, the layer on the far side takes {}, and the core needs "
                            "at least two edge lengths ({}) beside this layer and one beside both",
                            length(depth(i)), format_point(p), length(thickness), length(far), length(core)),
        in_file(source),
        clamp ? "a body at least one edge length thick everywhere (a smaller edge length)"
              : "smaller depths here or across the body, or clamping");
  }
  if (clamped > 0) {
    // Ease the thinned spots: a vertex keeps at most the mean of itself and
    // its neighbours, for a few rounds (depths only decrease).
    const auto nb = geometry::vertex_neighbours(outer.F, outer.V.rows());
    for (int round = 0; round < 3; ++round) {
      Eigen::VectorXd next = depth;
      for (Eigen::Index i = 0; i < depth.size(); ++i) {
        double sum = depth(i);
        for (int j : nb[std::size_t(i)]) sum += depth(j);
        next(i) = std::max(thinnest, std::min(depth(i), sum / double(nb[std::size_t(i)].size() + 1)));
      }
      depth = next;
    }
  }
  return clamped;
}

// The inner surface must be closed, clean and strictly inside the outer one.
void check_inner(const SurfaceMesh& inner, const SurfaceMesh& outer, const LayerOptions& options) {
  if (const auto pair = detail::cgal_self_intersection(inner)) {
    const Eigen::Vector3d at = inner.V.row(inner.F(pair->first, 0)).transpose();
    const Eigen::Vector3d on_outer = detail::SurfaceQueries(outer).closest(at).second;
    throw_input_error(
        fmt::format("the inner surface would intersect itself near {} (under the outer surface "
                    "at {}): the depth there is too large for the curvature of the body",
                    format_point(at), format_point(on_outer)),
        in_file(options.source),
        options.core_offset == CoreOffset::Normals
            ? "smaller depths where the surface is concave or thin, or the distance offset"
            : "smaller depths or a smaller edge length");
  }
  if (detail::cgal_surfaces_intersect(outer, inner) ||
      !detail::SurfaceQueries(outer).inside(inner.V.row(0).transpose())) {
    throw_input_error("the inner surface crosses the outer surface", in_file(options.source),
                      "depths smaller than the local thickness");
  }
  // A surface turned inside out passes the tests above but encloses a
  // negative volume.
  const double core_volume = enclosed_volume(inner);
  const double body_volume = enclosed_volume(outer);
  if (!(core_volume > 0.0) || !(core_volume < body_volume)) {
    throw_input_error(fmt::format("the core would enclose a volume of {} cm³ in a body of {} cm³: the depth "
                                  "turns it inside out",
                                  core_volume * 1e6, body_volume * 1e6),
                      in_file(options.source), "depths below the body's radius of curvature");
  }
}

SurfaceMesh inner_surface(const SurfaceMesh& outer, const Eigen::MatrixX3d& normals,
                          const Eigen::VectorXd& depth, const LayerOptions& options, double edge) {
  SurfaceMesh inner = outer;
  for (Eigen::Index i = 0; i < inner.V.rows(); ++i) {
    inner.V.row(i) -= depth(i) * normals.row(i);
  }
  taubin_smooth(inner, options.smoothing_rounds);
  if (options.edge_length > 0.0) inner = remesh_surface(inner, edge, options.remesh_iterations);
  check_inner(inner, outer, options);
  return inner;
}

// The level set at distance depth(closest skin point) inside the skin: the
// core is absent where the body is thinner than twice its depth.
SurfaceMesh distance_core(const SurfaceMesh& outer, const Eigen::VectorXd& depth,
                          const LayerOptions& options, double edge) {
  const auto depth_at = [&](Eigen::Index f, const Eigen::Vector3d& p) { return depth_on_face(outer, depth, f, p); };
  SurfaceMesh inner = repair_surface(detail::cgal_distance_offset(outer, depth_at, edge));
  if (inner.F.rows() < 4) {
    throw_input_error(fmt::format("no core is left: the body is nowhere thicker than twice the depth ({} at most)",
                                  length(depth.maxCoeff())),
                      in_file(options.source), "a smaller depth");
  }
  check_closed_surface(inner, options.source + " (core)");
  if (options.edge_length > 0.0) inner = remesh_surface(inner, edge, options.remesh_iterations);
  check_inner(inner, outer, options);
  return inner;
}

}  // namespace

CoreOffset parse_core_offset(std::string_view name) {
  if (name == "normals") return CoreOffset::Normals;
  if (name == "distance") return CoreOffset::Distance;
  throw_input_error(fmt::format("unknown core offset '{}'", name), {}, "normals or distance");
}

Eigen::VectorXd distance_to_surface(const SurfaceMesh& surface, const Eigen::MatrixX3d& points) {
  const detail::SurfaceQueries queries(surface);
  Eigen::VectorXd d(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) d(i) = queries.distance(points.row(i).transpose());
  return d;
}

LayerMesh make_layer(const SurfaceMesh& scan, const DepthSpec& depth,
                     const std::optional<Samples>& stiffness, const LayerOptions& options) {
  LayerMesh layer;
  const auto stage = [&options](std::string_view name) {
    if (options.on_stage) options.on_stage(name);
  };
  stage("repair");
  const SurfaceMesh repaired = repair_surface(scan);
  check_closed_surface(repaired, options.source);
  stage("remesh");
  layer.outer = options.edge_length > 0.0
                    ? remesh_surface(repaired, options.edge_length, options.remesh_iterations)
                    : repaired;
  if (options.grading) {
    if (!(options.edge_length > 0.0) || !options.contact_distance) {
      throw Error(ErrorKind::Internal, "a grading needs an edge length and the distance to the contact");
    }
    layer.outer = remesh_graded(layer.outer, options.edge_length, *options.grading, options.contact_distance,
                                options.remesh_iterations);
  }
  // Remeshing a part thinner than the edge length can fold it through itself.
  if (options.edge_length > 0.0) {
    try {
      check_closed_surface(layer.outer, options.source);
    } catch (const Error& e) {
      throw_input_error(fmt::format("remeshed to {} edges: {}", length(options.edge_length), e.what()),
                        in_file(options.source), "a smaller edge length where the body is thin");
    }
  }
  const double edge =
      options.edge_length > 0.0 ? options.edge_length : mean_edge_length(layer.outer);

  stage("depth");
  const Eigen::MatrixX3d normals = geometry::vertex_normals(layer.outer);
  layer.depth = depth_field(layer.outer, depth, options);
  if (options.clamp_depth && options.core_offset == CoreOffset::Distance) {
    throw_input_error("depth clamping was asked for with the distance offset, which needs none (its core "
                      "is simply absent where the body is thin)",
                      in_file(options.source), "clamping with the normals offset only");
  }
  if (options.core_offset == CoreOffset::Normals) {
    layer.depth_clamped =
        check_thickness(layer.outer, normals, layer.depth, edge, options.clamp_depth, options.source);
  }
  // Stiffness samples are located now, so bad ones fail before the meshing.
  const Eigen::VectorXd E =
      stiffness ? stiffness_field(layer.outer, *stiffness, options) : Eigen::VectorXd();
  stage("inner_surface");
  layer.core = options.core_offset == CoreOffset::Normals
                   ? inner_surface(layer.outer, normals, layer.depth, options, edge)
                   : distance_core(layer.outer, layer.depth, options, edge);

  TetQuality& quality = layer.quality;
  quality = options.quality;
  if (quality.max_volume == 0.0) quality.max_volume = std::pow(edge, 3) / (6.0 * std::sqrt(2.0));
  stage("tetrahedralize");
  const std::vector<Eigen::Vector3d> holes = inside_points(layer.core, edge);
  TetMesh raw = detail::tetgen_shells({&layer.outer, &layer.core}, holes, quality);

  // Drop tets inside the core (none when the hole points did their job).
  stage("core");
  const detail::SurfaceQueries core_queries(layer.core);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < raw.T.rows(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) centroid += raw.V.row(raw.T(t, c)).transpose() / 4.0;
    if (core_queries.inside(centroid)) {
      ++layer.dropped_in_core;
    } else {
      kept.push_back(t);
    }
  }
  // Compact vertices.
  std::vector<int> index(static_cast<std::size_t>(raw.V.rows()), -1);
  int next = 0;
  layer.tets.T.resize(static_cast<Eigen::Index>(kept.size()), 4);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    for (int c = 0; c < 4; ++c) {
      int& i = index[raw.T(kept[k], c)];
      if (i < 0) i = next++;
      layer.tets.T(Eigen::Index(k), c) = i;
    }
  }
  layer.tets.V.resize(next, 3);
  for (Eigen::Index i = 0; i < raw.V.rows(); ++i) {
    if (index[i] >= 0) layer.tets.V.row(index[i]) = raw.V.row(i);
  }
  layer.tets.region = Eigen::VectorXi::Ones(layer.tets.T.rows());

  // Boundary: outer or core, by which surface is nearer.
  const detail::SurfaceQueries outer_queries(layer.outer);
  const auto faces = boundary_faces(layer.tets);
  layer.tets.boundary.resize(static_cast<Eigen::Index>(faces.size()), 3);
  layer.tets.boundary_marker.resize(static_cast<Eigen::Index>(faces.size()));
  std::vector<bool> on_core(static_cast<std::size_t>(next), false);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) centroid += layer.tets.V.row(faces[f][c]).transpose() / 3.0;
    const bool core = core_queries.distance(centroid) < outer_queries.distance(centroid);
    layer.tets.boundary.row(Eigen::Index(f)) << faces[f][0], faces[f][1], faces[f][2];
    layer.tets.boundary_marker(Eigen::Index(f)) = core ? kCoreMarker : kOuterMarker;
    if (core) {
      for (int c = 0; c < 3; ++c) on_core[faces[f][c]] = true;
    }
  }
  for (int i = 0; i < next; ++i) {
    if (on_core[i]) layer.attached.push_back(i);
  }

  if (stiffness) {
    stage("stiffness");
    // Each tet vertex takes the value at its closest skin point; each tet the
    // mean of its corners (one closest-point query per vertex, not per tet).
    Eigen::VectorXd at_vertex(layer.tets.V.rows());
    for (Eigen::Index i = 0; i < layer.tets.V.rows(); ++i) {
      geometry::SurfacePoint q;
      std::tie(q.face, q.position) = outer_queries.closest(layer.tets.V.row(i).transpose());
      q.barycentric = geometry::closest_point_on_triangle(
          q.position, layer.outer.V.row(layer.outer.F(q.face, 0)).transpose(),
          layer.outer.V.row(layer.outer.F(q.face, 1)).transpose(),
          layer.outer.V.row(layer.outer.F(q.face, 2)).transpose());
      at_vertex(i) = geometry::evaluate_at(layer.outer, q, E)(0);
    }
    layer.youngs_modulus.resize(layer.tets.T.rows());
    for (Eigen::Index t = 0; t < layer.tets.T.rows(); ++t) {
      layer.youngs_modulus(t) = 0.25 * (at_vertex(layer.tets.T(t, 0)) + at_vertex(layer.tets.T(t, 1)) +
                                        at_vertex(layer.tets.T(t, 2)) + at_vertex(layer.tets.T(t, 3)));
    }
  }
  return layer;
}

LayerSummary summarize_layer(const LayerMesh& layer, const TetQuality& bounds) {
  LayerSummary s;
  s.quality = tet_statistics(layer.tets, bounds);
  s.outer_volume = enclosed_volume(layer.outer);
  s.core_volume = enclosed_volume(layer.core);
  s.layer_volume = s.quality.volume;
  const Eigen::VectorXd thickness = distance_to_surface(layer.core, layer.outer.V);
  s.thickness_min = thickness.minCoeff();
  s.thickness_mean = thickness.mean();
  s.thickness_max = thickness.maxCoeff();
  s.depth_min = layer.depth.minCoeff();
  s.depth_mean = layer.depth.mean();
  s.depth_max = layer.depth.maxCoeff();
  if (layer.youngs_modulus.size() > 0) {
    s.youngs_min = layer.youngs_modulus.minCoeff();
    s.youngs_max = layer.youngs_modulus.maxCoeff();
  }
  s.outer_triangles = layer.outer.F.rows();
  s.core_triangles = layer.core.F.rows();
  s.attached = static_cast<Eigen::Index>(layer.attached.size());
  s.dropped_in_core = layer.dropped_in_core;
  return s;
}

}  // namespace palpa::mesh
