#include "palpa/rest/rest.hpp"

#include <spdlog/spdlog.h>

#include "palpa/core/units.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "palpa/contact/contact.hpp"
#include "palpa/core/error.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::rest {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Eigen::MatrixX3i skin_faces(const TetMesh& mesh, const std::vector<int>& attached) {
  const tet::Boundary boundary = tet::boundary_of(mesh);
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
  const Eigen::MatrixX3i faces = skin_faces(body.mesh, body.attached);
  std::vector<int> index(static_cast<std::size_t>(body.mesh.V.rows()), -1);
  SurfaceMesh s;
  s.F.resize(faces.rows(), 3);
  int next = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      int& i = index[static_cast<std::size_t>(faces(f, c))];
      if (i < 0) i = next++;
      s.F(f, c) = i;
    }
  }
  s.V.resize(next, 3);
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] >= 0) s.V.row(index[v]) = body.mesh.V.row(static_cast<Eigen::Index>(v));
  }
  return s;
}

RestSimulation::RestSimulation(RestBody body, const SurfaceMesh& support, RestOptions options)
    : body_(std::move(body)), options_(std::move(options)) {
  tet::prepare_tet_mesh(body_.mesh, "body");
  model_ = std::make_unique<tet::ElasticModel>(body_.mesh, body_.materials, body_.element_material);
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
  system_ = std::make_unique<body::CoreSystem>(*model_, core);
  system_->set_gravity(options_.gravity);
  system_->set_regularization(options_.regularization);
  system_->set_true_hessian(true);

  boundary_faces_ = tet::boundary_of(mesh).faces;
  surface_faces_ = skin_faces(mesh, body_.attached);
  std::vector<char> on_skin(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (Eigen::Index f = 0; f < surface_faces_.rows(); ++f) {
    for (int c = 0; c < 3; ++c) on_skin[static_cast<std::size_t>(surface_faces_(f, c))] = 1;
  }
  for (std::size_t v = 0; v < on_skin.size(); ++v) {
    if (on_skin[v]) surface_.push_back(static_cast<int>(v));
  }
  if (surface_.empty()) throw Error(ErrorKind::Input, "the body has no skin: every boundary face touches the core");
  body_area_ = contact::vertex_areas(mesh.V, surface_faces_);

  support_ = std::make_unique<contact::Obstacle>(support, options_.support_name);
  support_area_ = contact::vertex_areas(support_->vertices(), support_->triangles());

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
  double k = options_.stiffness;
  if (automatic_) {
    if (!(load > 0.0)) {
      throw Error(ErrorKind::Input, "nothing presses the body onto the support (no gravity, no external force): "
                                    "give the contact stiffness instead of a target penetration");
    }
    k = contact::stiffness_for_penetration(load, std::max(10.0, 0.1 * static_cast<double>(surface_.size())),
                                           options_.target_penetration);
  }
  term_ = std::make_unique<sim3d::RigidContactTerm>(*support_, mesh.V, surface_faces_, k);
  mean_area_ = term_->mean_area();
  system_->add_term(term_.get());

  NewtonOptions opt;
  opt.line_search = options_.line_search;
  opt.max_iterations = options_.max_iterations;
  const double tol = options_.force_tolerance > 0.0
                         ? options_.force_tolerance
                         : 1e-6 * std::max(load, 1e-6) / static_cast<double>(surface_.size());
  opt.gradient_abs_tol = tol;
  opt.gradient_rel_tol = 0.0;
  opt.gradient_accept_tol = 100.0 * tol;
  newton_ = std::make_unique<NewtonSolver>(opt);
  x_ = Eigen::VectorXd::Zero(system_->num_dofs());
}

RestSimulation::~RestSimulation() = default;

RestResult RestSimulation::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  term_->reset_timers();
  RestResult r;
  constexpr int kMaxSolves = 12;
  // Spring areas are updated while they change by more than 1% of the
  // contact area, at most three times for one stiffness: a rim vertex that
  // touches in one solve and not the next must not cycle the re-solves.
  constexpr double kAreaTolerance = 0.01;
  constexpr int kMaxAreaUpdates = 3;
  int area_updates = 0;
  for (;;) {
    const NewtonResult res = newton_->solve(*system_, x_);
    r.newton_iterations += res.iterations;
    ++r.solves;
    r.residual = res.gradient_norm;
    if (!res.converged()) {
      throw Error(ErrorKind::Solver,
                  fmt::format("the resting equilibrium did not converge{}: {}",
                              term_->contacts().empty() ? " (the body has not reached the support)" : "",
                              res.message));
    }
    if (term_->contacts().empty()) {
      throw Error(ErrorKind::Solver, "the body is in equilibrium without touching the support: nothing presses it on");
    }
    const double ratio = term_->contacts().max_depth() / options_.target_penetration;
    spdlog::info("rest: solve {}: {} Newton iterations, {} contacts, k = {:.4g} N/m, deepest penetration {} ({:.2f}× the target)",
                 r.solves, res.iterations, term_->contacts().size(), term_->stiffness(),
                 format_quantity(term_->contacts().max_depth(), Dimension::Length), ratio);
    const bool k_ok = !automatic_ || (ratio > 0.85 && ratio < 1.15);
    if (r.solves == kMaxSolves) {
      if (!k_ok) {
        r.message = fmt::format("the penetration is {:.2f}× the target after {} solves", ratio, kMaxSolves);
      }
      break;
    }
    // The last solve always runs with the spring areas it ends with.
    const bool areas_changed =
        options_.update_areas && area_updates < kMaxAreaUpdates && term_->update_areas(kAreaTolerance) > 0.0;
    if (areas_changed) ++area_updates;
    if (k_ok && !areas_changed) break;
    if (!k_ok) {
      term_->set_stiffness(term_->stiffness() * std::clamp(ratio, 0.1, 10.0));
      area_updates = 0;
    }
  }

  const Eigen::VectorXd p = system_->positions(x_);
  r.core_translation = system_->core_translation(x_);
  r.core_rotation = system_->core_rotation(x_);
  const Eigen::Matrix3Xd f = term_->vertex_forces(p);
  const Eigen::Vector3d c = system_->core().centre + r.core_translation;
  for (Eigen::Index v = 0; v < f.cols(); ++v) {
    if (f.col(v).squaredNorm() == 0.0) continue;
    r.contact_force += f.col(v);
    r.contact_torque += (p.segment<3>(3 * v) - c).cross(f.col(v));
  }
  const body::CoreSpec& core = system_->core();
  r.load = options_.gravity * (model_->total_mass() + core.mass) + core.force;
  Eigen::Vector3d imbalance = r.contact_force + r.load;
  for (int a = 0; a < 3; ++a) {
    if (core.locked[static_cast<std::size_t>(a)]) imbalance[a] = 0.0;
  }
  r.balance_error = r.load.norm() > 0.0 ? imbalance.norm() / r.load.norm() : imbalance.norm();
  r.max_penetration = term_->contacts().max_depth();
  r.stiffness = term_->stiffness();
  r.contacts = static_cast<int>(term_->contacts().size());
  r.body_pressure = term_->pressures(p);
  r.min_det_f = model_->min_jacobian(system_->full_displacement(x_));

  // The support's side: its vertices against the deformed body. A support
  // vertex at depth δ carries the pressure of a body vertex at that depth,
  // 2kδ/Ā (the body's springs are k·A/Ā), so both sides show the same
  // pressure field.
  r.support_pressure = Eigen::VectorXd::Zero(support_->vertices().rows());
  for (const ReverseContact& rc : reverse_contacts()) {
    r.support_pressure[rc.support_vertex] = 2.0 * r.stiffness * rc.closest.distance / mean_area_;
    ++r.support_contacts;
  }
  r.detection_seconds = term_->detection_seconds();
  r.seconds = seconds_since(t0);
  return r;
}

std::vector<ReverseContact> RestSimulation::reverse_contacts() const {
  // The deformed boundary (skin and core shells bound the layer) as an
  // obstacle, its vertices renumbered.
  const Eigen::VectorXd p = system_->positions(x_);
  std::vector<int> to_compact(static_cast<std::size_t>(model_->num_vertices()), -1);
  std::vector<int> used;
  for (Eigen::Index fi = 0; fi < boundary_faces_.rows(); ++fi) {
    for (int k = 0; k < 3; ++k) {
      const int v = boundary_faces_(fi, k);
      if (to_compact[static_cast<std::size_t>(v)] < 0) {
        to_compact[static_cast<std::size_t>(v)] = static_cast<int>(used.size());
        used.push_back(v);
      }
    }
  }
  SurfaceMesh deformed;
  deformed.V.resize(static_cast<Eigen::Index>(used.size()), 3);
  for (std::size_t i = 0; i < used.size(); ++i) deformed.V.row(static_cast<Eigen::Index>(i)) = p.segment<3>(3 * used[i]).transpose();
  deformed.F.resize(boundary_faces_.rows(), 3);
  for (Eigen::Index fi = 0; fi < boundary_faces_.rows(); ++fi) {
    for (int k = 0; k < 3; ++k) deformed.F(fi, k) = to_compact[static_cast<std::size_t>(boundary_faces_(fi, k))];
  }
  contact::ObstacleOptions oo;
  oo.check_self_intersections = false;
  const contact::Obstacle body_surface(deformed, "the deformed body surface", oo);
  std::vector<ReverseContact> out;
  for (Eigen::Index v = 0; v < support_->vertices().rows(); ++v) {
    ReverseContact c;
    if (!body_surface.penetration(support_->world_vertex(static_cast<int>(v)), c.closest) || !c.closest.inside) continue;
    double area = 0.0;
    for (int k = 0; k < contact::feature_size(c.closest.feature); ++k) {
      int& b = c.closest.vertices[static_cast<std::size_t>(k)];
      b = used[static_cast<std::size_t>(b)];
      area += c.closest.weights[k] * body_area_[b];
    }
    if (!(area > 0.0)) continue;  // against the core shell: not a skin contact
    c.support_vertex = static_cast<int>(v);
    out.push_back(c);
  }
  return out;
}

RestState RestSimulation::state() const {
  RestState s;
  s.x = x_;
  s.core = system_->committed();
  s.spring_areas = term_->spring_area();
  s.stiffness = term_->stiffness();
  return s;
}

void RestSimulation::restore(const RestState& s) {
  if (s.x.size() != x_.size() || !s.x.allFinite()) {
    throw Error(ErrorKind::Input, fmt::format("a saved state has {} DOFs for a body with {}", s.x.size(), x_.size()));
  }
  term_->set_areas(s.spring_areas);
  term_->set_stiffness(s.stiffness);
  system_->set_committed(s.core);
  x_ = s.x;
}

void RestSimulation::set_support_vertices(const Eigen::MatrixX3d& V) {
  support_->set_vertices(V, false);
  support_area_ = contact::vertex_areas(support_->vertices(), support_->triangles());
}

UnstructuredGrid RestSimulation::body_grid(const RestResult& r) const {
  const Eigen::VectorXd u = system_->full_displacement(x_);
  const TetMesh& mesh = model_->mesh();
  UnstructuredGrid grid;
  grid.points.resize(mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) grid.points.row(v) = mesh.V.row(v) + u.segment<3>(3 * v).transpose();
  grid.cells.push_back(CellBlock{VtkCellType::Tetra, mesh.T});
  Eigen::MatrixXd disp(mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) disp.row(v) = u.segment<3>(3 * v).transpose();
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  const Eigen::Matrix3Xd f = term_->vertex_forces(system_->positions(x_));
  grid.point_data.push_back(DataArray{"contact_force_N", f.transpose()});
  grid.point_data.push_back(DataArray{"pressure_Pa", r.body_pressure});
  Eigen::VectorXd attached = Eigen::VectorXd::Zero(mesh.V.rows());
  for (int v : body_.attached) attached[v] = 1.0;
  grid.point_data.push_back(DataArray{"attached", attached});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", tet::ElasticModel::von_mises(model_->cauchy_stress(u))});
  return grid;
}

UnstructuredGrid RestSimulation::support_grid(const RestResult& r) const {
  UnstructuredGrid grid;
  grid.points.resize(support_->vertices().rows(), 3);
  for (Eigen::Index v = 0; v < grid.points.rows(); ++v) grid.points.row(v) = support_->world_vertex(static_cast<int>(v)).transpose();
  grid.cells.push_back(CellBlock{VtkCellType::Triangle, support_->triangles()});
  grid.point_data.push_back(DataArray{"pressure_Pa", r.support_pressure});
  return grid;
}

SurfaceMesh RestSimulation::deformed_skin() const {
  const Eigen::VectorXd p = system_->positions(x_);
  SurfaceMesh s;
  s.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), p.size() / 3, 3);
  s.F = surface_faces_;
  return s;
}

}  // namespace palpa::rest
