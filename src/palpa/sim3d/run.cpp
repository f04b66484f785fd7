// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

#include "palpa/body/area_updates.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/stopwatch.hpp"
#include "palpa/core/checkpoint.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/core/text.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/solve/equilibrium.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::sim3d {

namespace fs = std::filesystem;

namespace {

// Regularization K + αM of a body held by nothing but contact (before it
// touches): α = 1/T² with T = 10 ms, so an unsupported body falls about
// g·T² ≈ 1 mm per Newton step until it lands.
constexpr double kFreeFallAlpha = 1e4;  // [1/s²]

}  // namespace

Simulation::Simulation(const Scene& scene) : scene_(&scene) {
  for (const ObstacleSpec& o : scene.obstacles) {
    obstacles_.push_back(std::make_unique<contact::Obstacle>(o.mesh, fmt::format("obstacle '{}'", o.name)));
  }
  // The simulated mesh: all of it, or the part near the obstacles' deepest pose.
  const TetMesh* mesh = &scene.mesh;
  Eigen::VectorXi element_material = scene.element_material;
  if (scene.local.enabled) {
    pose(scene.steps);
    std::vector<const contact::Obstacle*> obs;
    for (const auto& o : obstacles_) obs.push_back(o.get());
    region_ = std::make_unique<ActiveRegion>(active_region(scene.mesh, obs, scene.local.margin));
    mesh = &region_->mesh;
    element_material.resize(static_cast<Eigen::Index>(region_->element.size()));
    for (std::size_t i = 0; i < region_->element.size(); ++i) {
      element_material[static_cast<Eigen::Index>(i)] = scene.element_material[region_->element[i]];
    }
    vertex_map_ = region_->vertex;
  } else {
    vertex_map_.resize(static_cast<std::size_t>(scene.mesh.V.rows()));
    for (std::size_t v = 0; v < vertex_map_.size(); ++v) vertex_map_[v] = static_cast<int>(v);
  }
  model_ = std::make_unique<tet::ElasticModel>(*mesh, scene.materials, element_material);
  model_->set_element(scene.element);

  // Supports (and the cut boundary of a local simulation).
  const Eigen::Index nv = model_->num_vertices();
  std::vector<int> to_sim(static_cast<std::size_t>(scene.mesh.V.rows()), -1);
  for (std::size_t v = 0; v < vertex_map_.size(); ++v) to_sim[static_cast<std::size_t>(vertex_map_[v])] = static_cast<int>(v);
  std::vector<char> fixed(static_cast<std::size_t>(3 * nv), 0);
  for (const FixedSpec& f : scene.fixed) {
    for (int v : f.vertices) {
      const int sv = to_sim[static_cast<std::size_t>(v)];
      if (sv < 0) continue;
      for (int c = 0; c < 3; ++c) {
        if (f.components[static_cast<std::size_t>(c)]) fixed[static_cast<std::size_t>(3 * sv + c)] = 1;
      }
    }
  }
  if (region_) {
    for (int v : region_->cut) fixed[3 * static_cast<std::size_t>(v)] = fixed[3 * static_cast<std::size_t>(v) + 1] = fixed[3 * static_cast<std::size_t>(v) + 2] = 1;
  }
  const bool held = std::any_of(fixed.begin(), fixed.end(), [](char c) { return c != 0; });
  system_ = std::make_unique<tet::StaticSystem>(*model_, fixed);
  system_->set_gravity(scene.gravity);
  if (!held) system_->set_regularization(kFreeFallAlpha);

  // Contact: the boundary vertices against every obstacle.
  const geometry::Boundary boundary = geometry::boundary_of(model_->mesh());
  boundary_area_ = geometry::vertex_areas(model_->mesh().V, boundary.faces);
  double edge_sum = 0.0;
  for (Eigen::Index f = 0; f < boundary.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      edge_sum += (model_->mesh().V.row(boundary.faces(f, c)) - model_->mesh().V.row(boundary.faces(f, (c + 1) % 3))).norm();
    }
  }
  const double h = edge_sum / (3.0 * static_cast<double>(boundary.faces.rows()));
  double young = 0.0;
  for (const tet::BodyMaterial& m : scene.materials) {
    young = std::max(young, material::small_strain_constants(*m.material).young());
  }
  tolerance_ = scene.solver.force_tolerance > 0.0 ? scene.solver.force_tolerance : 1e-8 * young * h * h;
  automatic_stiffness_ = !(scene.contact.stiffness > 0.0);
  // Only ever raised: any depth up to the target is accepted, and a
  // correction aims 10% beyond the proportional rule so that the re-solve
  // lands below it.
  contact::StiffnessPolicy policy;
  // The default target: 2% of the mean surface edge, and at most 1% of the
  // deepest path (a shallow poke is not measured against a coarse mesh).
  double deepest_path = 0.0;
  for (const ObstacleSpec& o : scene.obstacles) {
    if (o.has_path) deepest_path = std::max(deepest_path, o.depth);
  }
  policy.target = scene.contact.max_penetration > 0.0 ? scene.contact.max_penetration
                  : deepest_path > 0.0                ? std::min(0.02 * h, 0.01 * deepest_path)
                                                      : 0.02 * h;
  policy.low = 0.0;
  policy.high = 1.0;
  policy.overshoot = 1.1;
  stiffness_ = contact::StiffnessController(policy);
  double mean_area = 0.0;
  for (int v : boundary.vertices) mean_area += boundary_area_[v];
  mean_area /= std::max<double>(1.0, static_cast<double>(boundary.vertices.size()));
  // Automatic start: a vertex under a pressure of E0/10 sits at the target depth.
  // (Surface sampling: k is that pressure per depth.)
  const bool surface = scene.contact.sampling == body::ContactSampling::Surface;
  const double k0 = !automatic_stiffness_ ? scene.contact.stiffness
                    : surface             ? 0.1 * young / policy.target
                                          : contact::stiffness_for_pressure(0.1 * young, mean_area, policy.target);
  for (const auto& o : obstacles_) {
    terms_.push_back(std::make_unique<body::ContactTerm>(*o, model_->mesh().V, boundary.faces, k0,
                                                         scene.contact.sampling, scene.contact.subdivisions));
    terms_.back()->set_friction(scene.contact.friction);
    system_->add_term(terms_.back().get());
  }

  NewtonOptions opt;
  opt.line_search = scene.solver.line_search;
  opt.max_iterations = scene.solver.max_iterations;
  ToleranceModel{tolerance_}.apply(opt);
  newton_ = std::make_unique<NewtonSolver>(opt);
  x_ = Eigen::VectorXd::Zero(system_->num_dofs());
  pose(0);
}

Simulation::~Simulation() = default;

void Simulation::pose(int s) {
  const double t = static_cast<double>(s) / static_cast<double>(scene_->steps);
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    const ObstacleSpec& o = scene_->obstacles[i];
    contact::Pose p;
    p.R = o.rotation;
    p.t = o.position;
    if (o.has_path) p.t += t * o.depth * o.direction;
    obstacles_[i]->set_pose(p);
  }
}

void Simulation::set_state(const Eigen::VectorXd& x, const std::vector<double>& stiffness,
                           const std::vector<std::vector<double>>& spring_areas,
                           const std::vector<std::vector<std::array<double, 5>>>& anchors) {
  if (x.size() != system_->num_dofs() || stiffness.size() != terms_.size() ||
      spring_areas.size() != terms_.size() || (!anchors.empty() && anchors.size() != terms_.size())) {
    throw Error(ErrorKind::Input, "the saved state does not fit this scene's mesh");
  }
  x_ = x;
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    terms_[i]->set_stiffness(stiffness[i]);
    terms_[i]->set_areas(spring_areas[i]);
    terms_[i]->set_anchors(anchors.empty() ? std::vector<std::array<double, 5>>{} : anchors[i]);
  }
}

std::string Simulation::worst_residual() const {
  Eigen::VectorXd g;
  system_->gradient(x_, g);
  if (g.size() == 0 || !g.allFinite()) return "the residual is not finite";
  const std::vector<int>& dofs = system_->free_dofs();
  Eigen::VectorXd per_vertex = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(vertex_map_.size()));
  for (Eigen::Index i = 0; i < g.size(); ++i) {
    per_vertex[dofs[static_cast<std::size_t>(i)] / 3] += g[i] * g[i];
  }
  Eigen::Index local = 0;
  const double worst = std::sqrt(per_vertex.maxCoeff(&local));
  const int v = vertex_map_[static_cast<std::size_t>(local)];
  const Eigen::Vector3d at = scene_->mesh.V.row(v).transpose() * 1e3;
  return fmt::format("the largest unbalanced force is {:.3g} N at vertex {} (rest position {:.4g}, {:.4g}, {:.4g} mm)",
                     worst, v, at.x(), at.y(), at.z());
}

std::string Simulation::deepest_contact() const {
  std::string out;
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const contact::PenaltyContact& pc = terms_[i]->potential();
    const contact::SampleContact* c = pc.deepest();
    if (c == nullptr || pc.stiffness_of(*c) <= 0.0 || stiffness_.accepts(c->closest.distance)) continue;
    const contact::ContactSamples& samples = pc.samples();
    const auto s = static_cast<std::size_t>(c->sample);
    int slot = 0;
    for (int k = 1; k < samples.count(s); ++k) {
      if (samples.weights[s][k] > samples.weights[s][slot]) slot = k;
    }
    const int v = vertex_map_[static_cast<std::size_t>(samples.vertices[s][static_cast<std::size_t>(slot)])];
    const Eigen::Vector3d at = scene_->mesh.V.row(v).transpose() * 1e3;
    out += fmt::format("{}{}: {:.3g} mm deep at vertex {} (rest position {:.4g}, {:.4g}, {:.4g} mm)",
                       out.empty() ? "" : "; ", scene_->obstacles[i].name, c->closest.distance * 1e3, v, at.x(),
                       at.y(), at.z());
  }
  return out.empty() ? "no contact is above the target now" : out;
}

int Simulation::solve_static(StepRecord& r, Pass pass) {
  const NewtonResult res = solve_pass(*newton_, *system_, x_, pass);
  r.newton_iterations += res.iterations;
  r.factorizations += static_cast<int>(res.factorizations);
  r.residual = res.gradient_norm;
  r.tolerance = res.gradient_tolerance;
  if (!res.converged()) {
    throw Error(ErrorKind::Solver, fmt::format("step {} of {}: the equilibrium did not converge: {}; {}", r.step,
                                               scene_->steps, res.message, worst_residual()));
  }
  return res.iterations;
}

int Simulation::solve_dynamic(StepRecord& r) {
  const DynamicsSpec& d = scene_->dynamics;
  tet::BackwardEulerSystem dyn(*system_, d.time_step, {d.mass_damping, d.stiffness_damping});
  const double settle = d.settle > 0.0 ? d.settle : 1e-3 * target_penetration();
  Eigen::VectorXd v = Eigen::VectorXd::Zero(x_.size());
  for (int k = 0; k < d.max_steps; ++k) {
    dyn.begin_step(x_, v);
    Eigen::VectorXd next = x_;
    const NewtonResult res = newton_->solve(dyn, next);
    r.newton_iterations += res.iterations;
    r.factorizations += static_cast<int>(res.factorizations);
    if (!res.converged()) {
      throw Error(ErrorKind::Solver, fmt::format("step {} of {}, time step {}: the implicit step did not converge: {}",
                                                 r.step, scene_->steps, k + 1, res.message));
    }
    const double move = (next - x_).cwiseAbs().maxCoeff();
    v = (next - x_) / d.time_step;
    x_ = next;
    ++r.solves;
    if (move <= settle) {
      Eigen::VectorXd g;
      system_->gradient(x_, g);
      r.residual = g.size() > 0 ? g.cwiseAbs().maxCoeff() : 0.0;
      r.tolerance = tolerance_;
      return k + 1;
    }
  }
  throw Error(ErrorKind::Solver, fmt::format("step {} of {}: the body did not settle within {} time steps of {} s "
                                             "(largest move per step still above {:.3g} m); raise dynamics.max_steps "
                                             "or the damping",
                                             r.step, scene_->steps, d.max_steps, d.time_step, settle));
}

StepRecord Simulation::solve_step(int s) {
  const auto t0 = std::chrono::steady_clock::now();
  for (auto& t : terms_) t->reset_timers();
  StepRecord r;
  r.step = s;
  // Where the body was when the step began: contacts that stick are anchored
  // where their points met the obstacle.
  const Eigen::VectorXd reference = system_->positions(system_->full_displacement(x_));
  pose(s - 1);
  std::vector<contact::Pose> reference_pose;
  for (const auto& o : obstacles_) reference_pose.push_back(o->pose());
  pose(s);
  constexpr int kMaxCorrections = 12;
  const auto solve_once = [&](Pass pass) {
    if (scene_->dynamics.enabled) {
      solve_dynamic(r);  // (each time step to the final tolerance)
    } else {
      solve_static(r, pass);
      ++r.solves;
    }
  };
  // k is raised where the penetration exceeds the target; spring areas follow
  // the contact set (body/area_updates.hpp); contacts that stick are anchored
  // once both stand. The last solve always runs with what it ends with.
  body::AreaUpdates area_updates;
  const auto adjust = [&](int, bool last) {
    bool raised = false;
    for (auto& t : terms_) {
      const double depth = t->potential().max_depth();
      if (!automatic_stiffness_ || stiffness_.accepts(depth)) continue;
      if (!last) t->set_stiffness(stiffness_.next(t->stiffness(), depth));
      raised = true;
    }
    if (last) return raised ? Resolve::Stiffness : Resolve::None;
    const bool areas_changed = area_updates.update(terms_);
    if (raised) {
      area_updates.restart();
      return Resolve::Stiffness;
    }
    if (areas_changed) return Resolve::Areas;
    if (scene_->contact.friction == contact::Friction::Stick) {
      const Eigen::VectorXd now = system_->positions(system_->full_displacement(x_));
      int anchored = 0;
      for (std::size_t i = 0; i < terms_.size(); ++i) anchored += terms_[i]->anchor(now, reference, reference_pose[i]);
      if (anchored > 0) return Resolve::Anchors;
    }
    return Resolve::None;
  };
  if (run_equilibrium_loop(kMaxCorrections, solve_once, adjust).capped()) {
    throw Error(ErrorKind::Solver,
                fmt::format("step {} of {}: the penetration stays above the target {:.3g} mm after {} "
                            "corrections ({}); give contact.stiffness or a larger contact.max_penetration",
                            s, scene_->steps, target_penetration() * 1e3, kMaxCorrections, deepest_contact()));
  }
  const Eigen::VectorXd p = system_->positions(system_->full_displacement(x_));
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const ObstacleSpec& spec = scene_->obstacles[i];
    const body::ContactTerm& t = *terms_[i];
    ObstacleResult o;
    o.depth = spec.has_path ? spec.depth * static_cast<double>(s) / scene_->steps : 0.0;
    const contact::Wrench w = t.obstacle_wrench(p, obstacles_[i]->pose().t);
    o.force = w.force;
    o.torque = w.torque;
    o.indentation_force = spec.has_path ? -w.force.dot(spec.direction) : w.force.norm();
    o.contacts = static_cast<int>(t.potential().size());
    o.max_penetration = t.potential().max_depth();
    o.stiffness = t.stiffness();
    r.obstacles.push_back(o);
    r.detection_seconds += t.detection_seconds();
  }
  r.min_det_f = model_->min_jacobian(system_->full_displacement(x_));
  r.seconds = seconds_since(t0);
  return r;
}

UnstructuredGrid Simulation::body_grid() const {
  const Eigen::VectorXd u = system_->full_displacement(x_);
  const Eigen::VectorXd p = system_->positions(u);
  const TetMesh& mesh = model_->mesh();
  UnstructuredGrid grid;
  grid.points = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), mesh.V.rows(), 3);
  grid.cells.push_back(CellBlock{VtkCellType::Tetra, mesh.T});
  const Eigen::MatrixXd disp = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(u.data(), mesh.V.rows(), 3);
  grid.point_data.push_back(DataArray{"displacement_m", disp});
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, mesh.V.rows());
  Eigen::VectorXd pressure = Eigen::VectorXd::Zero(mesh.V.rows());
  for (const auto& t : terms_) {
    f += t->vertex_forces(p);
    pressure += t->pressures(p);
  }
  grid.point_data.push_back(DataArray{"contact_force_N", f.transpose()});
  grid.point_data.push_back(DataArray{"pressure_Pa", pressure});
  const Eigen::MatrixXd s = model_->cauchy_stress(u);
  grid.cell_data.push_back(DataArray{"cauchy_stress_xx_yy_zz_Pa", s.leftCols(3)});
  grid.cell_data.push_back(DataArray{"cauchy_stress_yz_xz_xy_Pa", s.rightCols(3)});
  grid.cell_data.push_back(DataArray{"von_mises_stress_Pa", tet::ElasticModel::von_mises(s)});
  Eigen::VectorXd det(mesh.T.rows());
  for (Eigen::Index e = 0; e < mesh.T.rows(); ++e) {
    det[e] = tet::deformation_gradient(model_->geometry(e), model_->element_positions(u, e)).determinant();
  }
  grid.cell_data.push_back(DataArray{"det_F", det});
  grid.cell_data.push_back(DataArray{"material", model_->element_material().cast<double>()});
  return grid;
}

UnstructuredGrid Simulation::obstacle_grid(std::size_t i) const {
  const contact::Obstacle& o = *obstacles_[i];
  UnstructuredGrid grid;
  grid.points.resize(o.vertices().rows(), 3);
  for (Eigen::Index v = 0; v < o.vertices().rows(); ++v) grid.points.row(v) = o.world_vertex(static_cast<int>(v)).transpose();
  grid.cells.push_back(CellBlock{VtkCellType::Triangle, o.triangles()});
  return grid;
}

// ---------------------------------------------------------------- run

namespace {

Json record_json(const StepRecord& r, const Scene& scene) {
  Json obs = Json::array();
  for (std::size_t i = 0; i < r.obstacles.size(); ++i) {
    const ObstacleResult& o = r.obstacles[i];
    obs.push_back({{"name", scene.obstacles[i].name},
                   {"depth_m", o.depth},
                   {"indentation_force_N", o.indentation_force},
                   {"force_N", {o.force[0], o.force[1], o.force[2]}},
                   {"torque_Nm", {o.torque[0], o.torque[1], o.torque[2]}},
                   {"contacts", o.contacts},
                   {"max_penetration_m", o.max_penetration},
                   {"stiffness_N_per_m", o.stiffness}});
  }
  return {{"step", r.step},
          {"obstacles", obs},
          {"newton_iterations", r.newton_iterations},
          {"solves", r.solves},
          {"factorizations", r.factorizations},
          {"residual_N", r.residual},
          {"tolerance_N", r.tolerance},
          {"seconds", r.seconds},
          {"detection_seconds", r.detection_seconds},
          {"min_det_F", r.min_det_f}};
}

std::string scene_fingerprint(const Scene& scene) {
  std::ifstream in(scene.file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return fingerprint(fmt::format("{}\n{} {}", text.str(), scene.mesh.V.rows(), scene.mesh.T.rows()));
}

void write_curves(const fs::path& out, const Scene& scene, const std::vector<Json>& records) {
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    if (!scene.obstacles[i].has_path) continue;
    std::vector<double> depth{0.0}, force{0.0}, fx{0.0}, fy{0.0}, fz{0.0};
    for (const Json& r : records) {
      const Json& o = r.at("obstacles").at(i);
      depth.push_back(o.at("depth_m").get<double>());
      force.push_back(o.at("indentation_force_N").get<double>());
      fx.push_back(o.at("force_N").at(0).get<double>());
      fy.push_back(o.at("force_N").at(1).get<double>());
      fz.push_back(o.at("force_N").at(2).get<double>());
    }
    CsvTable t;
    t.add_comment(fmt::format("palpa sim3d {}: obstacle '{}'; force_N pushes along the path, force_x/y/z_N act on "
                              "the obstacle",
                              scene.file.filename().string(), scene.obstacles[i].name));
    t.add_column("indentation_m", depth);
    t.add_column("force_N", force);
    t.add_column("force_x_N", fx);
    t.add_column("force_y_N", fy);
    t.add_column("force_z_N", fz);
    write_csv(out / fmt::format("force_{}.csv", scene.obstacles[i].name), t);
  }
}

}  // namespace

Json run(const Scene& scene, const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  OutputFolder folder(options.out, OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::Exclusive,
                      options.resume ? OutputFolder::Start::Resumed : OutputFolder::Start::Fresh);
  OutputFolder frames(options.out / "frames", OutputFolder::OnFailure::RemoveIfEmpty, OutputFolder::Lock::None);
  const fs::path state_path = options.out / "state.json";
  const std::string fp = scene_fingerprint(scene);
  Simulation sim(scene);

  std::vector<Json> records;
  std::vector<PvdEntry> body_frames;
  std::vector<std::vector<PvdEntry>> obstacle_frames(scene.obstacles.size());
  int start = 1;
  if (options.resume) {
    if (!fs::exists(state_path)) {
      throw Error(ErrorKind::Input, fmt::format("{}: there is no interrupted run to resume (no state.json)", options.out.string()));
    }
    const Json doc =
        read_checkpoint(state_path, {"sim3d", fp, "the scene differs from the interrupted run's", "the same scene file and mesh"});
    const JsonView v(doc, state_path.string());
    const std::vector<double> x = v.at("state").as_number_array();
    std::vector<std::vector<double>> areas;
    for (std::size_t i = 0; i < v.at("spring_areas").size(); ++i) {
      areas.push_back(v.at("spring_areas").at(i).as_number_array());
    }
    std::vector<std::vector<std::array<double, 5>>> anchors;
    if (const auto an = v.find("anchors")) {
      for (std::size_t i = 0; i < an->size(); ++i) {
        const std::vector<double> flat = an->at(i).as_number_array();
        if (flat.size() % 5 != 0) an->at(i).fail("not rows of 5 numbers", "(sample, face, w0, w1, w2) rows");
        auto& rows = anchors.emplace_back();
        for (std::size_t k = 0; k < flat.size(); k += 5) rows.push_back({flat[k], flat[k + 1], flat[k + 2], flat[k + 3], flat[k + 4]});
      }
    }
    sim.set_state(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())),
                  v.at("stiffness").as_number_array(), areas, anchors);
    // The state is saved after every step but the last: the next step is 2..steps,
    // with one record per step done.
    const JsonView next = v.at("next_step");
    if (next.as_integer() < 2 || next.as_integer() > scene.steps) {
      next.fail(fmt::format("step {} of a {}-step run", next.as_integer(), scene.steps),
                fmt::format("2 to {} (the step after the last one saved)", scene.steps));
    }
    start = static_cast<int>(next.as_integer());
    const JsonView saved = v.at("records");
    if (saved.size() != static_cast<std::size_t>(start - 1)) {
      saved.fail(fmt::format("{} step records before step {}", saved.size(), start),
                 fmt::format("{} (one per step done)", start - 1));
    }
    for (const Json& r : doc.at("records")) records.push_back(r);
    for (const Json& e : doc.at("body_frames")) body_frames.push_back({e.at(0).get<double>(), e.at(1).get<std::string>()});
    for (std::size_t i = 0; i < obstacle_frames.size(); ++i) {
      for (const Json& e : doc.at("obstacle_frames").at(i)) {
        obstacle_frames[i].push_back({e.at(0).get<double>(), e.at(1).get<std::string>()});
      }
    }
  } else if (fs::exists(state_path)) {
    throw Error(ErrorKind::Input, fmt::format("{} holds an interrupted run: resume it with --resume, or write to "
                                              "another folder", options.out.string()));
  }

  const auto summary = [&](bool complete) {
    Json steps = Json::array();
    int its = 0;
    double detect = 0.0, secs = 0.0;
    for (const Json& r : records) {
      steps.push_back(r);
      its += r.at("newton_iterations").get<int>();
      detect += r.at("detection_seconds").get<double>();
      secs += r.at("seconds").get<double>();
    }
    Json mesh = {{"vertices", scene.mesh.V.rows()}, {"tetrahedra", scene.mesh.T.rows()}};
    if (sim.region()) {
      mesh["simulated_vertices"] = sim.model().num_vertices();
      mesh["simulated_tetrahedra"] = sim.model().num_elements();
      mesh["cut_vertices"] = sim.region()->cut.size();
    }
    mesh["free_dofs"] = sim.system().num_dofs();
    mesh["element"] = element_json(sim.model());
    return Json{{"palpa_sim3d", 1},
                {"scene", scene.file.string()},
                {"complete", complete},
                {"steps_done", records.size()},
                {"steps", scene.steps},
                {"mesh", mesh},
                {"force_tolerance_N", sim.force_tolerance()},
                {"target_penetration_m", sim.target_penetration()},
                {"newton_iterations", its},
                {"seconds_in_steps", secs},
                {"detection_seconds", detect},
                {"records", steps}};
  };
  const auto frame_pair = [](const std::vector<PvdEntry>& v) {
    Json a = Json::array();
    for (const auto& e : v) a.push_back({e.time, e.file.string()});
    return a;
  };

  Progress progress("sim3d steps", static_cast<std::size_t>(scene.steps), options.progress);
  progress.advance(static_cast<std::size_t>(start - 1));
  for (int s = start; s <= scene.steps; ++s) {
    check_interrupt();
    if (options.stop_after_steps > 0 && s - start == options.stop_after_steps) {
      throw Error(ErrorKind::Interrupted, fmt::format("stopped after {} steps as asked", options.stop_after_steps));
    }
    StepRecord r;
    try {
      r = sim.solve_step(s);
    } catch (const Error& e) {
      // The converged steps stay written; the summary says where it stopped.
      if (e.kind() == ErrorKind::Solver) {
        Json failed = summary(false);
        failed["failed_step"] = s;
        failed["failure"] = e.what();
        write_json_file(options.out / "summary.json", failed);
      }
      throw;
    }
    records.push_back(record_json(r, scene));
    const double time = static_cast<double>(s) / scene.steps;
    if (scene.frames_every > 0 && (s % scene.frames_every == 0 || s == scene.steps)) {
      const std::string name = fmt::format("frames/body_{:04}.vtu", s);
      write_vtu(options.out / name, sim.body_grid());
      body_frames.push_back({time, name});
      write_pvd(options.out / "body.pvd", body_frames);
      for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
        const std::string oname = fmt::format("frames/{}_{:04}.vtu", scene.obstacles[i].name, s);
        write_vtu(options.out / oname, sim.obstacle_grid(i));
        obstacle_frames[i].push_back({time, oname});
        write_pvd(options.out / fmt::format("{}.pvd", scene.obstacles[i].name), obstacle_frames[i]);
      }
    }
    write_curves(options.out, scene, records);
    write_json_file(options.out / "summary.json", summary(s == scene.steps));
    if (s < scene.steps) {
      Json ofr = Json::array();
      for (const auto& f : obstacle_frames) ofr.push_back(frame_pair(f));
      std::vector<double> k;
      Json areas = Json::array(), anchors = Json::array();
      for (std::size_t i = 0; i < sim.num_obstacles(); ++i) {
        k.push_back(sim.contact_term(i).stiffness());
        areas.push_back(sim.contact_term(i).spring_area());
        std::vector<double> flat;
        for (const auto& row : sim.contact_term(i).potential().anchors()) flat.insert(flat.end(), row.begin(), row.end());
        anchors.push_back(flat);
      }
      const Eigen::VectorXd& x = sim.state();
      Json doc = checkpoint_document("sim3d", fp);
      doc.update(Json{{"next_step", s + 1},
                      {"state", std::vector<double>(x.data(), x.data() + x.size())},
                      {"stiffness", k},
                      {"spring_areas", areas},
                      {"anchors", anchors},
                      {"records", records},
                      {"body_frames", frame_pair(body_frames)},
                      {"obstacle_frames", ofr}});
      write_json_file(state_path, doc);
    }
    std::string note = fmt::format("{} Newton its", r.newton_iterations);
    if (!r.obstacles.empty()) note += fmt::format(", force {:.4g} N", r.obstacles[0].indentation_force);
    progress.set_note(note);
    progress.advance();
  }
  progress.finish();
  std::error_code ec;
  fs::remove(state_path, ec);
  Json s = summary(true);
  s["total_seconds"] = seconds_since(t0);
  write_json_file(options.out / "summary.json", s);
  frames.keep();
  folder.keep();
  return s;
}

}  // namespace palpa::sim3d
