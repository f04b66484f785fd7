// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/penalty_contact.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>

#include "palpa/core/error.hpp"

namespace palpa::contact {

namespace {

// Samples per task of the parallel loops: a closest-point query costs ~1 µs.
constexpr std::size_t kSampleGrain = 256;

}  // namespace

ContactSamples vertex_samples(std::span<const int> vertices, const Eigen::VectorXd& vertex_area) {
  ContactSamples s;
  s.vertices.reserve(vertices.size());
  s.area.reserve(vertices.size());
  for (int v : vertices) {
    s.vertices.push_back({v, -1, -1});
    s.area.push_back(vertex_area.size() > 0 ? vertex_area[v] : 0.0);
  }
  s.weights.assign(vertices.size(), Eigen::Vector3d(1.0, 0.0, 0.0));
  s.scale.assign(vertices.size(), 1.0);
  return s;
}

TriangleRule subdivision_rule(int n) {
  if (n < 1) throw Error(ErrorKind::Input, fmt::format("a triangle rule needs n ≥ 1 subdivisions, got {}", n));
  TriangleRule r;
  const double h = 1.0 / n, w = 1.0 / (static_cast<double>(n) * n);
  // Sub-triangles in barycentric steps (i, j) of the first two coordinates:
  // "up" triangles (i, j), (i+1, j), (i, j+1) and "down" ones (i+1, j),
  // (i, j+1), (i+1, j+1); their centroids.
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      const double a = (i + 1.0 / 3.0) * h, b = (j + 1.0 / 3.0) * h;
      r.barycentric.emplace_back(a, b, 1.0 - a - b);
      r.weight.push_back(w);
      if (i + j + 1 < n) {
        const double c = (i + 2.0 / 3.0) * h, d = (j + 2.0 / 3.0) * h;
        r.barycentric.emplace_back(c, d, 1.0 - c - d);
        r.weight.push_back(w);
      }
    }
  }
  return r;
}

ContactSamples surface_samples(const Eigen::MatrixX3d& rest, const Eigen::MatrixX3i& faces, const TriangleRule& rule) {
  ContactSamples s;
  const std::size_t n = static_cast<std::size_t>(faces.rows()) * rule.weight.size();
  s.vertices.reserve(n);
  s.weights.reserve(n);
  s.scale.reserve(n);
  s.area.reserve(n);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = rest.row(faces(f, 0)), b = rest.row(faces(f, 1)), c = rest.row(faces(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!(area > 0.0)) {
      throw Error(ErrorKind::Input, fmt::format("surface triangle {} (vertices {}, {}, {}) has no area", f, faces(f, 0),
                                                faces(f, 1), faces(f, 2)));
    }
    for (std::size_t q = 0; q < rule.weight.size(); ++q) {
      s.vertices.push_back({faces(f, 0), faces(f, 1), faces(f, 2)});
      s.weights.push_back(rule.barycentric[q]);
      s.scale.push_back(0.5 * rule.weight[q] * area);
      s.area.push_back(rule.weight[q] * area);
    }
  }
  return s;
}

Eigen::Matrix3d Stencil::block(const Matrix12d& H, int a, int b) const {
  const auto index = [&](int slot) { return on_surface(slot) ? 0 : slot - n + 1; };
  const auto factor = [&](int slot) { return on_surface(slot) ? weight[slot] : 1.0; };
  const Eigen::Matrix3d h = H.block<3, 3>(3 * index(a), 3 * index(b));
  if (n == 1) return h;  // a vertex sample: N = 1
  return factor(a) * factor(b) * h;
}

PenaltyContact::PenaltyContact(ContactSamples samples, double k, std::string name)
    : name_(std::move(name)), samples_(std::move(samples)) {
  assert(samples_.weights.size() == samples_.size() && samples_.scale.size() == samples_.size());
  set_stiffness(k);
}

void PenaltyContact::set_stiffness(double k) {
  if (!std::isfinite(k) || !(k > 0.0)) {
    throw Error(ErrorKind::Input, fmt::format("{}: contact stiffness must be > 0, got {}", name_, k));
  }
  k_ = k;
}

void PenaltyContact::set_scale(std::vector<double> scale) {
  assert(scale.size() == samples_.size());
  samples_.scale = std::move(scale);
}

void PenaltyContact::set_excluded(std::vector<char> excluded_obstacle_vertices) {
  excluded_ = std::move(excluded_obstacle_vertices);
}

bool PenaltyContact::excluded(const ClosestPoint& c) const {
  if (excluded_.empty()) return false;
  for (int i = 0; i < feature_size(c.feature); ++i) {
    if (excluded_[static_cast<std::size_t>(c.vertices[static_cast<std::size_t>(i)])] != 0) return true;
  }
  return false;
}

Eigen::Vector3d PenaltyContact::position(int sample, Points points) const {
  const std::size_t s = static_cast<std::size_t>(sample);
  const std::array<int, 3>& v = samples_.vertices[s];
  if (v[1] < 0) return points.col(v[0]);  // a vertex sample: exactly the vertex
  const Eigen::Vector3d& N = samples_.weights[s];
  Eigen::Vector3d x = N[0] * points.col(v[0]) + N[1] * points.col(v[1]);
  if (v[2] >= 0) x += N[2] * points.col(v[2]);
  return x;
}

Stencil PenaltyContact::stencil_of(const SampleContact& c) const {
  Stencil s;
  const std::size_t i = static_cast<std::size_t>(c.sample);
  s.sample = c.sample;
  s.n = samples_.count(i);
  s.surface_vertex = samples_.vertices[i];
  s.weight = samples_.weights[i];
  s.m = feature_size(c.closest.feature);
  s.obstacle_vertex = c.closest.vertices;
  return s;
}

FeatureGeometry PenaltyContact::geometry_of(const Obstacle& obstacle, const SampleContact& c) const {
  FeatureGeometry g = feature_geometry(obstacle, c.closest);
  if (c.stuck) {
    g.stuck = true;
    g.stuck_weights = c.closest.weights;
  }
  return g;
}

void PenaltyContact::set_friction(Friction friction) {
  friction_ = friction;
  anchor_face_.assign(friction == Friction::Stick ? samples_.size() : 0, -1);
  anchor_weights_.assign(anchor_face_.size(), Eigen::Vector3d::Zero());
  for (SampleContact& c : contacts_) c.stuck = false;
}

std::vector<std::array<double, 5>> PenaltyContact::anchors() const {
  std::vector<std::array<double, 5>> rows;
  for (std::size_t s = 0; s < anchor_face_.size(); ++s) {
    if (anchor_face_[s] < 0) continue;
    const Eigen::Vector3d& w = anchor_weights_[s];
    rows.push_back({static_cast<double>(s), static_cast<double>(anchor_face_[s]), w[0], w[1], w[2]});
  }
  return rows;
}

void PenaltyContact::set_anchors(const std::vector<std::array<double, 5>>& rows, const Obstacle& obstacle) {
  if (friction_ != Friction::Stick) {
    if (rows.empty()) return;
    throw Error(ErrorKind::Input, fmt::format("{}: anchors given to a frictionless contact", name_));
  }
  std::fill(anchor_face_.begin(), anchor_face_.end(), -1);
  for (const auto& r : rows) {
    const double s = r[0], f = r[1];
    const Eigen::Vector3d w(r[2], r[3], r[4]);
    if (!(s >= 0.0 && s < static_cast<double>(samples_.size()) && s == std::floor(s) && f >= 0.0 &&
          f < static_cast<double>(obstacle.triangles().rows()) && f == std::floor(f) && w.allFinite() &&
          w.minCoeff() >= 0.0 && std::abs(w.sum() - 1.0) < 1e-9)) {
      throw Error(ErrorKind::Input, fmt::format("{}: anchor (sample {}, face {}) does not fit", name_, s, f));
    }
    anchor_face_[static_cast<std::size_t>(s)] = static_cast<int>(f);
    anchor_weights_[static_cast<std::size_t>(s)] = w;
  }
}

namespace {

// The point with weights w on face f of the obstacle, where it is now [m].
Eigen::Vector3d face_point(const Obstacle& obstacle, int f, const Eigen::Vector3d& w) {
  const Eigen::MatrixX3i& F = obstacle.triangles();
  return w[0] * obstacle.world_vertex(F(f, 0)) + w[1] * obstacle.world_vertex(F(f, 1)) +
         w[2] * obstacle.world_vertex(F(f, 2));
}

// Barycentric weights of x (on or near the triangle) on its corners, clamped
// into the triangle.
Eigen::Vector3d barycentric(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, d = x - a;
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double det = g11 * g22 - g12 * g12;
  double u = (g22 * e1.dot(d) - g12 * e2.dot(d)) / det;
  double v = (g11 * e2.dot(d) - g12 * e1.dot(d)) / det;
  u = std::clamp(u, 0.0, 1.0);
  v = std::clamp(v, 0.0, 1.0 - u);
  return {1.0 - u - v, u, v};
}

}  // namespace

int PenaltyContact::anchor(const Obstacle& obstacle, Points points, Points reference, const Pose& reference_pose) {
  if (friction_ != Friction::Stick) return 0;
  int added = 0;
  const Eigen::MatrixX3i& F = obstacle.triangles();
  const Pose& now = obstacle.pose();
  for (const SampleContact& c : contacts_) {
    const auto s = static_cast<std::size_t>(c.sample);
    if (anchor_face_[s] >= 0) continue;
    // The reference position as seen from the obstacle then, placed where
    // that is now.
    const Eigen::Vector3d body = reference_pose.R.transpose() * (position(c.sample, reference) - reference_pose.t);
    const ClosestPoint at = obstacle.closest_point(now.R * body + now.t);
    const int f = at.triangle;
    anchor_face_[s] = f;
    anchor_weights_[s] = barycentric(at.point, obstacle.world_vertex(F(f, 0)), obstacle.world_vertex(F(f, 1)),
                                     obstacle.world_vertex(F(f, 2)));
    ++added;
  }
  if (added > 0) commit(obstacle, points);
  return added;
}

double PenaltyContact::detected_energy(const Obstacle& obstacle, Points points) const {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, samples_.size(), kSampleGrain), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double sum) {
        ClosestPoint c;
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
          const Eigen::Vector3d x = position(static_cast<int>(s), points);
          if (!obstacle.penetration(x, c) || excluded(c)) continue;
          if (!anchor_face_.empty() && anchor_face_[s] >= 0) {
            sum += k_ * samples_.scale[s] * (x - face_point(obstacle, anchor_face_[s], anchor_weights_[s])).squaredNorm();
            continue;
          }
          sum += k_ * samples_.scale[s] * c.distance * c.distance;
        }
        return sum;
      },
      std::plus<>());
}

void PenaltyContact::commit(const Obstacle& obstacle, Points points) {
  slot_.resize(samples_.size());
  hit_.resize(samples_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples_.size(), kSampleGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t s = r.begin(); s != r.end(); ++s) {
                        hit_[s] = obstacle.penetration(position(static_cast<int>(s), points), slot_[s]) &&
                                          !excluded(slot_[s])
                                      ? 1
                                      : 0;
                      }
                    });
  contacts_.clear();
  const bool stick = !anchor_face_.empty();
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    if (hit_[s] == 0) {
      if (stick) anchor_face_[s] = -1;  // it left the obstacle: released
      continue;
    }
    SampleContact c{static_cast<int>(s), slot_[s]};
    if (stick && anchor_face_[s] >= 0) {
      const int f = anchor_face_[s];
      const Eigen::MatrixX3i& F = obstacle.triangles();
      c.stuck = true;
      c.closest.feature = Feature::Face;
      c.closest.triangle = f;
      c.closest.vertices = {F(f, 0), F(f, 1), F(f, 2)};
      c.closest.weights = anchor_weights_[s];
      c.closest.point = face_point(obstacle, f, anchor_weights_[s]);
    }
    contacts_.push_back(c);
  }
}

double PenaltyContact::max_depth() const {
  double m = 0.0;
  for (const SampleContact& c : contacts_) m = std::max(m, c.closest.distance);
  return m;
}

const SampleContact* PenaltyContact::deepest() const noexcept {
  const SampleContact* d = nullptr;
  for (const SampleContact& c : contacts_) {
    if (d == nullptr || c.closest.distance > d->closest.distance) d = &c;
  }
  return d;
}

double PenaltyContact::energy(const Obstacle& obstacle, Points points) const {
  double e = 0.0;
  for (const SampleContact& c : contacts_) {
    e += penalty_energy(position(c.sample, points), geometry_of(obstacle, c), stiffness_of(c));
  }
  return e;
}

namespace {

// g_v += N_i·g over the sample's surface vertices.
void scatter(const Stencil& st, const Eigen::Vector3d& g, Eigen::Ref<Eigen::Matrix3Xd> out) {
  if (st.n == 1) {
    out.col(st.surface_vertex[0]) += g;
    return;
  }
  for (int i = 0; i < st.n; ++i) out.col(st.surface_vertex[static_cast<std::size_t>(i)]) += st.weight[i] * g;
}

}  // namespace

void PenaltyContact::add_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == points.cols());
  for (const SampleContact& c : contacts_) {
    scatter(stencil_of(c), penalty_gradient(position(c.sample, points), geometry_of(obstacle, c), stiffness_of(c)),
            grad);
  }
}

void PenaltyContact::add_obstacle_gradient(const Obstacle& obstacle, Points points,
                                           Eigen::Ref<Eigen::Matrix3Xd> grad) const {
  assert(grad.cols() == obstacle.vertices().rows());
  for (const SampleContact& c : contacts_) {
    const FeatureGeometry g = geometry_of(obstacle, c);
    const Vector12d full = penalty_gradient_full(position(c.sample, points), g, stiffness_of(c));
    for (int i = 0; i < g.m; ++i) grad.col(c.closest.vertices[static_cast<std::size_t>(i)]) += full.segment<3>(3 * (i + 1));
  }
}

void PenaltyContact::add_forces(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> on_points,
                                Eigen::Ref<Eigen::Matrix3Xd> on_obstacle) const {
  assert(on_points.cols() == points.cols());
  assert(on_obstacle.cols() == 0 || on_obstacle.cols() == obstacle.vertices().rows());
  for (const SampleContact& c : contacts_) {
    const FeatureGeometry g = geometry_of(obstacle, c);
    const Stencil st = stencil_of(c);
    if (on_obstacle.cols() == 0) {
      scatter(st, -penalty_gradient(position(c.sample, points), g, stiffness_of(c)), on_points);
      continue;
    }
    const Vector12d full = penalty_gradient_full(position(c.sample, points), g, stiffness_of(c));
    scatter(st, -full.head<3>(), on_points);
    for (int i = 0; i < g.m; ++i) {
      on_obstacle.col(c.closest.vertices[static_cast<std::size_t>(i)]) -= full.segment<3>(3 * (i + 1));
    }
  }
}

void PenaltyContact::add_contact_areas(Points rest, Points points, Eigen::Ref<Eigen::VectorXd> on_points,
                                       Eigen::Ref<Eigen::VectorXd> on_obstacle) const {
  assert(rest.cols() == points.cols() && on_points.size() == points.cols());
  for (const SampleContact& c : contacts_) {
    const auto s = static_cast<std::size_t>(c.sample);
    const std::array<int, 3>& v = samples_.vertices[s];
    double area = samples_.area[s];
    if (samples_.count(s) == 3) {
      const double now = (points.col(v[1]) - points.col(v[0])).cross(points.col(v[2]) - points.col(v[0])).norm();
      const double then = (rest.col(v[1]) - rest.col(v[0])).cross(rest.col(v[2]) - rest.col(v[0])).norm();
      if (then > 0.0) area *= now / then;
    }
    for (int i = 0; i < samples_.count(s); ++i) on_points[v[static_cast<std::size_t>(i)]] += samples_.weights[s][i] * area;
    if (on_obstacle.size() == 0) continue;
    for (int i = 0; i < feature_size(c.closest.feature); ++i) {
      on_obstacle[c.closest.vertices[static_cast<std::size_t>(i)]] += c.closest.weights[i] * area;
    }
  }
}

Wrench PenaltyContact::obstacle_wrench(const Obstacle& obstacle, Points points, const Eigen::Vector3d& about) const {
  Wrench w;
  for (const SampleContact& c : contacts_) {
    const Eigen::Vector3d p = position(c.sample, points);
    const Eigen::Vector3d a = sliding_anchor(p, geometry_of(obstacle, c)).point;
    const Eigen::Vector3d reaction = 2.0 * stiffness_of(c) * (p - a);  // −f
    w.force += reaction;
    w.torque += (a - about).cross(reaction);
  }
  return w;
}

void PenaltyContact::add_hessian_product(const Obstacle& obstacle, Points points, Points v_points,
                                         Points v_obstacle, Eigen::Ref<Eigen::Matrix3Xd> out_points,
                                         Eigen::Ref<Eigen::Matrix3Xd> out_obstacle) const {
  assert(v_points.cols() == points.cols() && out_points.cols() == points.cols());
  const bool has_v = v_obstacle.cols() > 0, has_out = out_obstacle.cols() > 0;
  for_each_stencil_hessian(obstacle, points, [&](const Stencil& s, const Matrix12d& H) {
    Vector12d v = Vector12d::Zero();
    v.head<3>() = position(s.sample, v_points);  // Σ N_i v_i: the same linear map
    if (has_v) {
      for (int i = 0; i < s.m; ++i) v.segment<3>(3 * (i + 1)) = v_obstacle.col(s.obstacle_vertex[static_cast<std::size_t>(i)]);
    }
    const Vector12d Hv = H * v;
    scatter(s, Hv.head<3>(), out_points);
    if (!has_out) return;
    for (int i = 0; i < s.m; ++i) out_obstacle.col(s.obstacle_vertex[static_cast<std::size_t>(i)]) += Hv.segment<3>(3 * (i + 1));
  });
}

}  // namespace palpa::contact
