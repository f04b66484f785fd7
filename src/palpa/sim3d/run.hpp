// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Running a scene (scene.hpp): a sequence of static equilibria (or settled
// implicit dynamics) along the obstacles' paths, with penalty contact.
//
// Each step: pose every obstacle, then solve from the previous step's state
// (Newton, CHOLMOD with the symbolic analysis reused). With an automatic
// contact stiffness (a target maximum penetration), a step whose deepest
// penetration exceeds the target is solved again with k raised by the
// contact::StiffnessController (the stiffness only grows, so later steps start
// from a k that already suits them).
//
// Force tolerance (automatic): 1e-8·E0·h² [N], E0 the largest small-strain
// Young's modulus, h the mean edge length; steps also accept 100× that where
// rounding stops progress.
//
// Outputs of run() in the output folder (each file atomic, rewritten after
// every step, so an interrupted run leaves a consistent set): force_<name>.csv
// for each obstacle with a path (indentation_m, force_N, and the force
// components on the obstacle), body.pvd + frames/body_NNNN.vtu (displacement,
// contact force and pressure per vertex; Cauchy stress, von Mises, det F and
// material per tet), <name>.pvd + frames/<name>_NNNN.vtu (the posed
// obstacles), summary.json, and state.json (the checkpoint that --resume reads;
// it is removed when the run completes).

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "palpa/body/contact_term.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/stiffness.hpp"
#include "palpa/core/json.hpp"
#include "palpa/core/progress.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/sim3d/local.hpp"
#include "palpa/sim3d/scene.hpp"
#include "palpa/solve/equilibrium.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::sim3d {

struct ObstacleResult {
  double depth = 0.0;                                 // travel along the path [m]
  Eigen::Vector3d force = Eigen::Vector3d::Zero();    // contact force on the obstacle [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();   // about the obstacle's origin [N·m]
  double indentation_force = 0.0;  // −force·direction: the push along the path [N]
  int contacts = 0;
  double max_penetration = 0.0;    // [m]
  double stiffness = 0.0;          // k used [N/m]
};

struct StepRecord {
  int step = 0;                    // 1 … steps
  std::vector<ObstacleResult> obstacles;
  int newton_iterations = 0;       // over all solves of the step
  int solves = 0;                  // 1 + stiffness corrections (or dynamics steps)
  int factorizations = 0;
  double residual = 0.0;           // ‖g‖∞ at the end [N]
  double tolerance = 0.0;          // [N]
  double seconds = 0.0;
  double detection_seconds = 0.0;  // collision detection within `seconds`
  double min_det_f = 0.0;          // smallest det F over the tets
};

class Simulation {
 public:
  // Keeps a reference to the scene, which must outlive the simulation (a
  // temporary scene does not compile).
  explicit Simulation(const Scene& scene);
  explicit Simulation(const Scene&& scene) = delete;
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const Scene& scene() const noexcept { return *scene_; }
  const tet::ElasticModel& model() const noexcept { return *model_; }
  tet::StaticSystem& system() noexcept { return *system_; }
  // The simulated mesh's vertex -> scene mesh vertex (identity unless local).
  const std::vector<int>& vertex_map() const noexcept { return vertex_map_; }
  const ActiveRegion* region() const noexcept { return region_.get(); }
  std::size_t num_obstacles() const noexcept { return obstacles_.size(); }
  const contact::Obstacle& obstacle(std::size_t i) const { return *obstacles_[i]; }
  const body::ContactTerm& contact_term(std::size_t i) const { return *terms_[i]; }
  double force_tolerance() const noexcept { return tolerance_; }
  double target_penetration() const noexcept { return stiffness_.policy().target; }

  // Poses the obstacles for step s (0 = start) and solves from the current
  // state. Throws palpa::Error (Solver) if Newton fails, naming the step and
  // why; (Interrupted) on Ctrl-C (the state stays at the last accepted iterate).
  StepRecord solve_step(int s);

  // The free DOFs and the full displacement (3N) of the current state.
  const Eigen::VectorXd& state() const noexcept { return x_; }
  // Restores a saved state: free DOFs, each obstacle's k, spring areas and
  // stick anchors (contact::PenaltyContact::anchors(); none when frictionless).
  void set_state(const Eigen::VectorXd& x, const std::vector<double>& stiffness,
                 const std::vector<std::vector<double>>& spring_areas,
                 const std::vector<std::vector<std::array<double, 5>>>& anchors = {});
  Eigen::VectorXd displacement() const { return system_->full_displacement(x_); }

  // The body at the current state, for output.
  UnstructuredGrid body_grid() const;
  UnstructuredGrid obstacle_grid(std::size_t i) const;

 private:
  void pose(int s);
  int solve_static(StepRecord& r, Pass pass);
  // For failure messages: the vertex with the largest unbalanced force, and
  // each obstacle's deepest contact above the target penetration.
  std::string worst_residual() const;
  std::string deepest_contact() const;
  int solve_dynamic(StepRecord& r);

  const Scene* scene_;
  std::unique_ptr<ActiveRegion> region_;
  std::vector<int> vertex_map_;
  std::unique_ptr<tet::ElasticModel> model_;
  std::unique_ptr<tet::StaticSystem> system_;
  std::vector<std::unique_ptr<contact::Obstacle>> obstacles_;
  std::vector<std::unique_ptr<body::ContactTerm>> terms_;
  std::unique_ptr<NewtonSolver> newton_;
  Eigen::VectorXd x_;
  Eigen::VectorXd boundary_area_;  // per simulated vertex [m²]
  double tolerance_ = 0.0;
  // Raises k where a step's penetration exceeds the target (automatic only).
  contact::StiffnessController stiffness_{contact::StiffnessPolicy{}};
  bool automatic_stiffness_ = false;
};

struct RunOptions {
  std::filesystem::path out;
  bool resume = false;
  Progress::Style progress = Progress::Style::Auto;
  // Stop as if interrupted after this many steps of this call (0: run all):
  // splits a long run into sessions, and lets tests interrupt at a known step.
  int stop_after_steps = 0;
};

// Runs every step of the scene, writing the outputs described above. Returns
// the summary JSON (also written). Throws palpa::Error: (Input) for a resume
// without a matching state.json, (Solver) for a step that does not converge
// (outputs of the steps before it stay), (Interrupted) on Ctrl-C.
Json run(const Scene& scene, const RunOptions& options);

}  // namespace palpa::sim3d
