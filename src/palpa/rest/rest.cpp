// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/rest.hpp"

#include <spdlog/spdlog.h>

#include "palpa/core/units.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <fmt/format.h>

#include "palpa/body/area_updates.hpp"
#include "palpa/contact/contact.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/submesh.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/mesh/tetrahedralize.hpp"
#include "palpa/rest/coupled.hpp"
#include "palpa/rest/measurements.hpp"
#include "palpa/solve/adjoint.hpp"
#include "palpa/core/stopwatch.hpp"
#include "palpa/solve/equilibrium.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::rest {

Eigen::MatrixX3i skin_faces(const TetMesh& mesh, const std::vector<int>& attached) {
  const geometry::Boundary boundary = geometry::boundary_of(mesh);
  std::vector<char> on_core(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : attached) on_core[static_cast<std::size_t>(v)] = 1;
  std::vector<Eigen::Index> skin;
  for (Eigen::Index f = 0; f < boundary.faces.rows(); ++f) {
    bool touches = false;
    for (int c = 0; c < 3; ++c) touches = touches || on_core[static_cast<std::size_t>(boundary.faces(f, c))];
    if (!touches) skin.push_back(f);
  }
  Eigen::MatrixX3i out(static_cast<Eigen::Index>(skin.size()), 3);
  for (std::size_t i = 0; i < skin.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = boundary.faces.row(skin[i]);
  return out;
}

SurfaceMesh body_skin(const RestBody& body) {
  return geometry::submesh(body.mesh.V, skin_faces(body.mesh, body.attached)).mesh;
}

double place_clear_of(RestBody& body, const SurfaceMesh& support, const Eigen::Vector3d& up, double margin) {
  if (!(up.norm() > 0.0)) return 0.0;
  const double lift = lift_clear_of(body, support, up, margin);
  if (lift > 0.0) body.mesh.V.rowwise() += (lift * up.normalized()).transpose();
  return lift;
}

double lift_clear_of(const RestBody& body, const SurfaceMesh& support, const Eigen::Vector3d& up, double margin) {
  const Eigen::MatrixX3i faces = skin_faces(body.mesh, body.attached);
  std::vector<int> skin(static_cast<std::size_t>(faces.size()));
  for (Eigen::Index i = 0; i < faces.size(); ++i) skin[static_cast<std::size_t>(i)] = faces.data()[i];
  std::sort(skin.begin(), skin.end());
  skin.erase(std::unique(skin.begin(), skin.end()), skin.end());
  const contact::Obstacle obstacle(support, "the support");
  const Eigen::Vector3d u = up.normalized();
  const auto clear = [&](double t) {
    for (int v : skin) {
      if (obstacle.inside(body.mesh.V.row(v).transpose() + t * u)) return false;
    }
    return true;
  };
  if (clear(0.0)) return 0.0;
  double lo = 0.0, hi = 1e-3;
  while (!clear(hi)) {
    lo = hi;
    hi *= 2.0;
    if (hi > 100.0) throw Error(ErrorKind::Solver, "the body lies inside the support and no lift along gravity frees it");
  }
  while (hi - lo > 1e-3 * hi) {
    const double mid = 0.5 * (lo + hi);
    (clear(mid) ? hi : lo) = mid;
  }
  return hi + margin;
}

RestSimulation::RestSimulation(RestBody body, const SurfaceMesh& support, RestOptions options)
    : body_(std::move(body)), options_(std::move(options)) {
  tet::prepare_tet_mesh(body_.mesh, "body");
  model_ = std::make_unique<tet::ElasticModel>(body_.mesh, body_.materials, body_.element_material);
  model_->set_element(body_.element);
  const TetMesh& mesh = model_->mesh();

  body::CoreSpec core = options_.core;
  core.attached = body_.attached;
  if (!options_.core_centre_given && !core.attached.empty()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : core.attached) {
      if (v >= 0 && v < mesh.V.rows()) c += mesh.V.row(v).transpose();
    }
    core.centre = c / static_cast<double>(core.attached.size());
  }
  system_ = std::make_unique<body::CoreSystem>(*model_, core, PsdProjection::None);
  system_->set_gravity(options_.gravity);
  system_->set_regularization(options_.regularization);

  boundary_faces_ = geometry::boundary_of(mesh).faces;
  surface_faces_ = skin_faces(mesh, body_.attached);
  std::vector<char> on_skin(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (Eigen::Index f = 0; f < surface_faces_.rows(); ++f) {
    for (int c = 0; c < 3; ++c) on_skin[static_cast<std::size_t>(surface_faces_(f, c))] = 1;
  }
  for (std::size_t v = 0; v < on_skin.size(); ++v) {
    if (on_skin[v]) surface_.push_back(static_cast<int>(v));
  }
  if (surface_.empty()) throw Error(ErrorKind::Input, "the body has no skin: every boundary face touches the core");
  body_area_ = geometry::vertex_areas(mesh.V, surface_faces_);

  support_ = std::make_unique<contact::Obstacle>(support, options_.support_name);
  support_rest_ = support_->vertices();
  support_area_ = geometry::vertex_areas(support_rest_, support_->triangles());
  support_fixed_.assign(static_cast<std::size_t>(support_rest_.rows()), 0);
  if (options_.deformable_support) build_deformable_support();

  // The body must start above the support.
  int inside = 0;
  int first = -1;
  for (int v : surface_) {
    if (support_->inside(mesh.V.row(v).transpose())) {
      if (first < 0) first = v;
      ++inside;
    }
  }
  if (inside > 0) {
    throw Error(ErrorKind::Input,
                fmt::format("the body starts inside {}: {} of its {} skin vertices are inside (e.g. vertex {} at "
                            "({:.4g}, {:.4g}, {:.4g}) m); place it slightly above the support",
                            options_.support_name, inside, surface_.size(), first, mesh.V(first, 0), mesh.V(first, 1),
                            mesh.V(first, 2)));
  }

  const double load = options_.gravity.norm() * (model_->total_mass() + core.mass) + core.force.norm();
  automatic_ = !(options_.stiffness > 0.0);
  update_areas_ = options_.update_areas;
  double k = options_.stiffness;
  if (automatic_) {
    if (!(load > 0.0)) {
      throw Error(ErrorKind::Input, "nothing presses the body onto the support (no gravity, no external force): "
                                    "give the contact stiffness instead of a target penetration");
    }
    k = contact::stiffness_for_penetration(load, std::max(10.0, 0.1 * static_cast<double>(surface_.size())),
                                           options_.target_penetration);
    contact::StiffnessPolicy policy;
    policy.target = options_.target_penetration;
    // A body's curved skin on a support: the contact grows with the approach
    // (α = ½) until two solves measure it. (k may still move by at most 10×
    // at once: a larger jump from a state sunk many times the target deep
    // leaves Newton too far from the new equilibrium.)
    policy.exponent = 0.5;
    policy.measure_exponent = true;
    stiffness_.emplace(policy);
    // Surface sampling: k is the pressure per depth, 2k/Ā for that vertex
    // spring k of mean skin area Ā.
    if (options_.sampling == body::ContactSampling::Surface) {
      k *= 2.0 / (body_area_.sum() / static_cast<double>(surface_.size()));
    }
  }
  // Two passes on a deformable support share the spring law: each at k/2.
  term_ = std::make_unique<body::ContactTerm>(*support_, mesh.V, surface_faces_, k / contact_passes(), options_.sampling,
                                              options_.subdivisions);
  if (!support_model_) system_->add_term(term_.get());  // else the coupled system evaluates it
  if (support_model_) {
    std::vector<int> surface(static_cast<std::size_t>(support_rest_.rows()));
    for (std::size_t j = 0; j < surface.size(); ++j) surface[j] = static_cast<int>(j);
    coupled_ = std::make_unique<CoupledSystem>(*system_, *support_system_, *support_, std::move(surface), *term_,
                                               options_.subdivisions);
  }

  NewtonOptions opt;
  opt.line_search = options_.line_search;
  opt.max_iterations = options_.max_iterations;
  ToleranceModel tolerance;
  tolerance.tolerance = options_.force_tolerance > 0.0
                            ? options_.force_tolerance
                            : 1e-6 * std::max(load, 1e-6) / static_cast<double>(surface_.size());
  // By default, where rounding stops progress (a contact kink on a curved
  // support), an out-of-balance force up to 1e-6 of the load is accepted.
  if (!(options_.force_tolerance > 0.0)) {
    tolerance.accept_factor = std::max(tolerance.accept_factor, static_cast<double>(surface_.size()));
  }
  tolerance.apply(opt);
  newton_ = std::make_unique<NewtonSolver>(opt);
  x_ = Eigen::VectorXd::Zero(system_->num_dofs());
}

RestSimulation::~RestSimulation() = default;

void RestSimulation::build_deformable_support() {
  const DeformableSupport& d = *options_.deformable_support;
  const std::string& name = options_.support_name;
  if (!d.material) throw Error(ErrorKind::Input, fmt::format("the deformable {} has no material", name));
  if (!(d.edge >= 0.0) || !std::isfinite(d.edge)) {
    throw Error(ErrorKind::Input, fmt::format("the deformable {}: its tet edge must be ≥ 0 m, got {}", name, d.edge));
  }
  if (!(d.base_tolerance >= 0.0) || !std::isfinite(d.base_tolerance)) {
    throw Error(ErrorKind::Input, fmt::format("the deformable {}: its base tolerance must be ≥ 0 m, got {}", name,
                                              d.base_tolerance));
  }
  mesh::TetQuality q;
  if (d.edge > 0.0) q.max_volume = d.edge * d.edge * d.edge / (6.0 * std::sqrt(2.0));
  TetMesh tets = mesh::tetrahedralize(SurfaceMesh{support_rest_, support_->triangles()}, q);
  const Eigen::Index ns = support_rest_.rows();
  if (tets.V.rows() < ns || !tets.V.topRows(ns).isApprox(support_rest_, 1e-12)) {
    throw Error(ErrorKind::Internal, fmt::format("meshing the deformable {} moved its surface vertices", name));
  }
  tet::prepare_tet_mesh(tets, name);
  support_model_ = std::make_unique<tet::ElasticModel>(std::move(tets),
                                                       std::vector<tet::BodyMaterial>{{d.material, 0.0}});
  // The base: the vertices lowest along gravity (−z without gravity).
  const Eigen::Vector3d down =
      options_.gravity.norm() > 0.0 ? Eigen::Vector3d(options_.gravity.normalized()) : Eigen::Vector3d(0.0, 0.0, -1.0);
  const Eigen::MatrixX3d& V = support_model_->mesh().V;
  const Eigen::VectorXd depth = V * down;
  const double lowest = depth.maxCoeff();
  std::vector<char> fixed(static_cast<std::size_t>(3 * V.rows()), 0);
  Eigen::Index held = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (depth[v] < lowest - d.base_tolerance) continue;
    fixed[static_cast<std::size_t>(3 * v)] = fixed[static_cast<std::size_t>(3 * v + 1)] =
        fixed[static_cast<std::size_t>(3 * v + 2)] = 1;
    if (v < ns) support_fixed_[static_cast<std::size_t>(v)] = 1;
    ++held;
  }
  if (held < 3) {
    throw Error(ErrorKind::Input, fmt::format("the deformable {} has {} vertices on its base (within {} of the lowest "
                                              "along gravity): it needs a flat base to stand on",
                                              name, held, format_quantity(d.base_tolerance, Dimension::Length)));
  }
  support_system_ = std::make_unique<tet::StaticSystem>(*support_model_, std::move(fixed), PsdProjection::None);
  support_x_ = Eigen::VectorXd::Zero(support_system_->num_dofs());
  spdlog::info("rest: {} is deformable: {} tets, {} vertices, {} of them held at its base", name,
               support_model_->num_elements(), support_model_->num_vertices(), held);
}

Eigen::VectorXd RestSimulation::coupled_dofs() const {
  Eigen::VectorXd y(x_.size() + support_x_.size());
  y << x_, support_x_;
  return y;
}

void RestSimulation::set_pass_stiffness(double k) {
  if (coupled_) {
    coupled_->set_stiffness(k);
  } else {
    term_->set_stiffness(k);
  }
}

bool RestSimulation::support_vertex_fixed(int j) const { return support_fixed_.at(static_cast<std::size_t>(j)) != 0; }

RestResult RestSimulation::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  term_->reset_timers();
  RestResult r;
  constexpr int kMaxSolves = 12;
  body::AreaUpdates area_updates;
  if (stiffness_) stiffness_->restart();
  double ratio = 0.0;
  const auto solve_once = [&](Pass pass) {
    NewtonResult res;
    if (coupled_) {
      Eigen::VectorXd y(x_.size() + support_x_.size());
      y << x_, support_x_;
      res = solve_pass(*newton_, *coupled_, y, pass);
      x_ = y.head(x_.size());
      support_x_ = y.tail(support_x_.size());
      coupled_->place_obstacle(y);  // where the solution is, not the last trial
    } else {
      res = solve_pass(*newton_, *system_, x_, pass);
    }
    r.newton_iterations += res.iterations;
    ++r.solves;
    r.residual = res.gradient_norm;
    if (!res.converged()) {
      throw Error(ErrorKind::Solver,
                  fmt::format("the resting equilibrium did not converge{}: {}",
                              term_->potential().empty() ? " (the body has not reached the support)" : "",
                              res.message));
    }
    if (term_->potential().empty()) {
      throw Error(ErrorKind::Solver, "the body is in equilibrium without touching the support: nothing presses it on");
    }
    ratio = term_->potential().max_depth() / options_.target_penetration;
    spdlog::log(options_.log_solves ? spdlog::level::info : spdlog::level::debug,
                "rest: solve {}: {} Newton iterations, {} contacts, k = {:.4g} {}, deepest penetration {} ({:.2f}× the "
                "target)",
                r.solves, res.iterations, term_->potential().size(), contact_stiffness(),
                options_.sampling == body::ContactSampling::Surface ? "Pa/m" : "N/m",
                format_quantity(term_->potential().max_depth(), Dimension::Length), ratio);
  };
  // The last solve always runs with the spring areas it ends with.
  const auto adjust = [&](int, bool last) {
    const double depth = term_->potential().max_depth();
    const bool k_ok = !automatic_ || stiffness_->accepts(depth);
    if (last) return k_ok ? Resolve::None : Resolve::Stiffness;
    body::ContactTerm* const terms[] = {term_.get()};
    const bool areas_changed = options_.update_areas && area_updates.update(terms);
    if (!k_ok) {
      set_pass_stiffness(stiffness_->next(term_->stiffness(), depth));
      area_updates.restart();
      return Resolve::Stiffness;
    }
    return areas_changed ? Resolve::Areas : Resolve::None;
  };
  const EquilibriumLoopResult loop = run_equilibrium_loop(kMaxSolves, solve_once, adjust);
  if (loop.capped()) r.message = fmt::format("the penetration is {:.2f}× the target after {} solves", ratio, kMaxSolves);

  measure(*this, r);
  r.detection_seconds = term_->detection_seconds();
  r.seconds = seconds_since(t0);
  return r;
}

RestResult RestSimulation::refreeze_contact_model() {
  if (!stiffness_) throw Error(ErrorKind::Input, "the contact stiffness was given: there is no rule to choose it anew");
  automatic_ = true;
  options_.update_areas = update_areas_;
  try {
    RestResult r = solve();
    freeze_contact_model();
    return r;
  } catch (...) {
    freeze_contact_model();
    throw;
  }
}

std::pair<double, double> RestSimulation::accepted_penetration() const noexcept {
  if (!stiffness_) return {0.0, std::numeric_limits<double>::infinity()};
  return {stiffness_->policy().low, stiffness_->policy().high};
}

RestState RestSimulation::state() const {
  RestState s;
  s.x = x_;
  s.core = system_->committed();
  s.spring_areas = term_->spring_area();
  s.stiffness = term_->stiffness();
  s.support = support_x_;
  return s;
}

void RestSimulation::restore(const RestState& s) {
  if (s.x.size() != x_.size() || !s.x.allFinite()) {
    throw Error(ErrorKind::Input, fmt::format("a saved state has {} DOFs for a body with {}", s.x.size(), x_.size()));
  }
  if (s.support.size() != support_x_.size() || !s.support.allFinite()) {
    throw Error(ErrorKind::Input, fmt::format("a saved state has {} support DOFs for a support with {}",
                                              s.support.size(), support_x_.size()));
  }
  support_x_ = s.support;
  term_->set_areas(s.spring_areas);
  set_pass_stiffness(s.stiffness);
  system_->set_committed(s.core);
  x_ = s.x;
}

void RestSimulation::set_support_vertices(const Eigen::MatrixX3d& V) {
  if (V.rows() != support_rest_.rows()) {
    throw Error(ErrorKind::Input, fmt::format("{} support vertices for a support of {}", V.rows(), support_rest_.rows()));
  }
  if (support_model_) {
    Eigen::MatrixX3d all = support_model_->mesh().V;
    all.topRows(V.rows()) = V;
    support_model_->set_rest_positions(all);  // Solver error if a tet inverts; nothing changed then
    support_rest_ = V;
    coupled_->place_obstacle(coupled_dofs());
  } else {
    support_->set_vertices(V, false);
    support_rest_ = V;
  }
  support_area_ = geometry::vertex_areas(support_rest_, support_->triangles());
}

}  // namespace palpa::rest
