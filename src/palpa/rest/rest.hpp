// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A body resting on a support (thesis §7.3): the soft layer on its rigid core
// (body/core_system.hpp) under gravity and an external wrench, pressed onto a
// closed support surface by penalty contact with sliding anchors (by default
// integrated over the skin's triangles, RestOptions::sampling), solved for
// static equilibrium; then the contact pressures on both sides
// (bidirectional, Fig. 7.4) from one set of nodal contact forces: the
// traction per deformed area a mat would read, recovered on the skin and on
// the support where they are (rest/measurements.hpp), so that each map
// integrates to the contact force over the surface it is drawn on.
//
// The support is rigid and fixed, or deformable (§7.4.3,
// RestOptions::deformable_support): then its inside is meshed with tets, its
// base held, and body, support and a two-pass contact are solved together
// (rest/coupled.hpp).
//
// The body starts slightly above the support and falls onto it: while nothing
// touches, the Newton system is K + αM (§7.3.4). With an automatic penalty
// stiffness (a target maximum penetration, 0.3 mm by default as in the thesis)
// k starts from the load shared by a tenth of the body's surface vertices,
// and the equilibrium is solved again with k scaled by depth/target until the
// deepest penetration is within 15% of the target.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "palpa/body/contact_term.hpp"
#include "palpa/body/core_system.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/stiffness.hpp"
#include "palpa/report/pressure_metrics.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/model.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::rest {

class CoupledSystem;

struct RestBody {
  TetMesh mesh;                             // the layer, positively oriented [m]
  std::vector<int> attached;                // vertices on the core surface
  std::vector<tet::BodyMaterial> materials;
  Eigen::VectorXi element_material;         // empty: all materials[0]
  tet::ElementChoice element;
};

// The body's skin: the boundary faces of the layer with no corner on the core
// (outward, rows of the tet mesh's V).
Eigen::MatrixX3i skin_faces(const TetMesh& mesh, const std::vector<int>& attached);
// The skin as a closed surface of its own (vertices renumbered).
SurfaceMesh body_skin(const RestBody& body);

// How far the body must move along `up` so that none of its skin vertices
// lies inside the closed `support` (0 when none does; else the smallest such
// distance, to 1e-3 of it, plus `margin`). A design re-solved from scratch
// places the body this way when the optimized shape rose into where the scene
// puts it. Throws when no lift up to 100 m clears it.
double lift_clear_of(const RestBody& body, const SurfaceMesh& support, const Eigen::Vector3d& up, double margin);
// Moves the body by lift_clear_of along `up` (nothing when up is zero);
// returns the lift [m].
double place_clear_of(RestBody& body, const SurfaceMesh& support, const Eigen::Vector3d& up, double margin);

// A deformable support (thesis §7.4.3): the inside of the support's closed
// surface meshed with tets (TetGen, the surface kept as it is), of one
// hyperelastic material, its base held in place. Its own weight is left out
// (it does not press on the body).
struct DeformableSupport {
  std::shared_ptr<const material::Material> material;
  // Largest tet edge inside [m] (a TetGen volume bound, edge³/(6√2)); 0: only
  // TetGen's quality bounds.
  double edge = 0.0;
  // Vertices within this height of the lowest one (along gravity) are fixed [m].
  double base_tolerance = 1e-3;
};

struct RestOptions {
  body::CoreSpec core;  // attached is taken from the body; centre: see below
  bool core_centre_given = false;  // else c0 = the mean of the attached vertices
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  double target_penetration = 3e-4;  // [m]
  // k > 0 fixes it (no automatic rule): [Pa/m] with Surface sampling, [N/m]
  // with Vertices (RestResult::stiffness gives it back in the same unit).
  double stiffness = 0.0;
  LineSearchKind line_search = LineSearchKind::BacktrackingThenBrent;
  int max_iterations = 300;
  double force_tolerance = 0.0;      // [N]; 0: 1e-6 of the load over the surface vertices (accepted up to 1e-6 of the load where rounding stops progress)
  double regularization = 1e4;       // α [1/s²] before landing
  // Where the contact springs sit on the skin (body/contact_term.hpp):
  // Surface integrates the tractions over the skin's triangles
  // (`subdivisions`² points each), so the nodal forces are the consistent
  // loads of the pressure field and both maps carry the load; Vertices is
  // the node-to-surface contact of the thesis.
  body::ContactSampling sampling = body::ContactSampling::Surface;
  int subdivisions = 2;
  // Vertices: spring areas follow the contact between solves
  // (contact/spring_areas.hpp). Off: they stay as they are, so the
  // equilibrium is one smooth function of the support's shape (shape
  // optimization).
  bool update_areas = true;
  // Each solve logs a line (Newton iterations, contacts, k, penetration); a
  // caller that solves many times (the design) turns it down to debug.
  bool log_solves = true;
  std::string support_name = "support";
  // Set: the support deforms (see DeformableSupport); else it is rigid.
  std::optional<DeformableSupport> deformable_support;
};

struct RestResult {
  Eigen::Vector3d core_translation = Eigen::Vector3d::Zero();  // [m]
  Eigen::Matrix3d core_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d contact_force = Eigen::Vector3d::Zero();   // support on body [N]
  Eigen::Vector3d contact_torque = Eigen::Vector3d::Zero();  // about the core's centre, deformed [N·m]
  Eigen::Vector3d load = Eigen::Vector3d::Zero();            // gravity on body + core + external force [N]
  double balance_error = 0.0;        // |contact + load| / |load| (free directions only)
  double max_penetration = 0.0;      // [m]
  double stiffness = 0.0;            // k [N/m]
  int contacts = 0;                  // springs in contact (skin samples)
  int support_contacts = 0;          // support vertices with a pressure
  int reverse_contacts = 0;          // deformable: support-surface samples held out of the skin
  int newton_iterations = 0;
  int solves = 0;
  double seconds = 0.0;
  double detection_seconds = 0.0;
  double residual = 0.0;             // ‖g‖∞ [N]
  double min_det_f = 0.0;
  double support_max_displacement = 0.0;  // deformable support [m]
  double support_min_det_f = 1.0;         // deformable support
  Eigen::Vector3d support_base_force = Eigen::Vector3d::Zero();  // deformable: the ground on its base [N]
  // Per vertex, 0 off contact: the contact pressure, the normal traction per
  // deformed area (rest/measurements.hpp) [Pa].
  Eigen::VectorXd body_pressure;     // per body vertex
  Eigen::VectorXd support_pressure;  // per support vertex
  // Σ p_i A_i of each map over its vertex areas where it is drawn [N]: the
  // magnitudes of the nodal contact forces summed, equal to the load where
  // the forces are parallel to it.
  double body_map_force = 0.0;
  double support_map_force = 0.0;
  // What a pressure-mapping mat would read on each side
  // (report/pressure_metrics.hpp): the body's map on its deformed skin, the
  // support's where its vertices are.
  report::PressureMetrics body_metrics;
  report::PressureMetrics support_metrics;
  std::string message;
};

// Everything a solve starts from: with the same body and support it restores
// a simulation exactly (a warm start, a checkpoint).
struct RestState {
  Eigen::VectorXd x;                   // CoreSystem DOFs
  body::CoreSystem::Committed core;    // committed core pose
  std::vector<double> spring_areas;    // per body vertex [m²]
  double stiffness = 0.0;              // k [N/m]
  Eigen::VectorXd support;             // a deformable support's DOFs (empty if rigid)
};

class RestSimulation {
 public:
  // support: closed surface in world coordinates. Throws palpa::Error (Input)
  // for a support that is not a closed, manifold, outward surface, a core
  // without attached vertices or with nothing free, and a body that starts
  // inside the support (it must start above it). With
  // options.deformable_support the inside of the surface is meshed with tets
  // (its surface vertices keep their numbering).
  RestSimulation(RestBody body, const SurfaceMesh& support, RestOptions options);
  ~RestSimulation();
  RestSimulation(const RestSimulation&) = delete;
  RestSimulation& operator=(const RestSimulation&) = delete;

  // Solves for the equilibrium (warm-started from the current state). Throws
  // palpa::Error (Solver) when Newton fails, (Interrupted) on Ctrl-C.
  RestResult solve();

  const tet::ElasticModel& model() const noexcept { return *model_; }
  body::CoreSystem& system() noexcept { return *system_; }
  const body::CoreSystem& system() const noexcept { return *system_; }
  // The support's surface, where it is now (deformed, for a deformable one).
  const contact::Obstacle& support() const noexcept { return *support_; }
  // The support's surface at rest (its shape as made) [m]: the design's X.
  const Eigen::MatrixX3d& support_rest_vertices() const noexcept { return support_rest_; }
  bool deformable_support() const noexcept { return coupled_ != nullptr; }
  // A deformable support's tets (nullptr if rigid), its DOFs and whether
  // surface vertex j is held in place (its base; false for a rigid support).
  const tet::ElasticModel* support_model() const noexcept { return support_model_.get(); }
  CoupledSystem* coupled_system() noexcept { return coupled_.get(); }
  const CoupledSystem* coupled_system() const noexcept { return coupled_.get(); }
  const tet::StaticSystem* support_system() const noexcept { return support_system_.get(); }
  const Eigen::VectorXd& support_dofs() const noexcept { return support_x_; }
  bool support_vertex_fixed(int j) const;
  // Body and support DOFs together (deformable support).
  Eigen::VectorXd coupled_dofs() const;
  const Eigen::VectorXd& dofs() const noexcept { return x_; }
  const RestBody& body() const noexcept { return body_; }
  const RestOptions& options() const noexcept { return options_; }
  const body::ContactTerm& contact_term() const noexcept { return *term_; }
  // The contact's pressure law: a depth δ means a pressure kδ (Surface
  // sampling, k [Pa/m]) or 2kδ/Ā (Vertices, k [N/m], Ā the mean skin
  // vertex area). On a deformable support the support's surface presses on
  // the body's skin too (two passes, rest/coupled.hpp), each pass with half
  // of k, so that where both surfaces sink into each other alike the
  // pressure is the same; its pressures are the nodal forces of both passes
  // over the vertices' areas (rest/measurements.hpp).
  double contact_passes() const noexcept { return options_.deformable_support ? 2.0 : 1.0; }
  double contact_stiffness() const noexcept { return term_->stiffness() * contact_passes(); }
  NewtonSolver& newton() noexcept { return *newton_; }
  const std::vector<int>& surface_vertices() const noexcept { return surface_; }
  const Eigen::MatrixX3i& boundary_faces() const noexcept { return boundary_faces_; }
  const Eigen::VectorXd& skin_area() const noexcept { return body_area_; }  // per body vertex, at rest [m²]
  const Eigen::VectorXd& support_area() const noexcept { return support_area_; }  // per support vertex, at rest [m²]

  RestState state() const;
  // Throws palpa::Error (Input) for a state of another body.
  void restore(const RestState& s);
  // Moves the support's vertices (world [m], same triangles and count); the
  // next solve starts from the current state. For a deformable support these
  // are its rest positions (its inner tet vertices stay); palpa::Error
  // (Solver) if that inverts a tet.
  void set_support_vertices(const Eigen::MatrixX3d& V);
  // Measurements, the shape derivative and the output grids of a state are
  // free functions: rest/measurements.hpp, rest/adjoint.hpp, rest/output.hpp.

  // Keeps k and the spring areas as they are in later solves (no automatic
  // correction, no area updates): the equilibrium becomes one smooth function
  // of the support's shape.
  void freeze_contact_model() noexcept {
    automatic_ = false;
    options_.update_areas = false;
  }
  void set_log_solves(bool on) noexcept { options_.log_solves = on; }
  // Chooses the contact model anew at the current state and freezes it
  // again: a solve warm-started from the state with the automatic stiffness
  // rule (k corrected until the deepest penetration is on target) and, as
  // the options had it, spring-area updates. For a simulation built with the
  // automatic stiffness: palpa::Error (Input) if k was given; a failed solve
  // throws (Solver) and leaves the model frozen.
  RestResult refreeze_contact_model();
  // The depth-to-target ratios the automatic rule accepts ([low, high]);
  // {0, ∞} when k was given.
  std::pair<double, double> accepted_penetration() const noexcept;
  const Eigen::MatrixX3i& surface_faces() const noexcept { return surface_faces_; }  // outer skin, tet-mesh rows

 private:
  void build_deformable_support();
  // k of each contact pass [N/m] (both passes on a deformable support).
  void set_pass_stiffness(double k);

  RestBody body_;
  RestOptions options_;
  std::unique_ptr<tet::ElasticModel> model_;
  std::unique_ptr<body::CoreSystem> system_;
  std::unique_ptr<contact::Obstacle> support_;
  std::unique_ptr<body::ContactTerm> term_;
  std::unique_ptr<NewtonSolver> newton_;
  std::vector<int> surface_;          // body boundary vertices not attached to the core
  Eigen::MatrixX3i surface_faces_;    // boundary faces without attached corners
  Eigen::MatrixX3i boundary_faces_;   // the whole boundary (skin and core shells)
  Eigen::VectorXd body_area_;         // per vertex [m²]
  Eigen::VectorXd support_area_;      // per support vertex [m²]
  Eigen::VectorXd x_;
  bool automatic_ = true;
  bool update_areas_ = true;  // the options' spring-area updates, before any freeze
  // The automatic stiffness rule (set when automatic_).
  std::optional<contact::StiffnessController> stiffness_;
  // The support at rest, and a deformable support's tets, system and DOFs.
  Eigen::MatrixX3d support_rest_;
  std::unique_ptr<tet::ElasticModel> support_model_;
  std::unique_ptr<tet::StaticSystem> support_system_;
  std::unique_ptr<CoupledSystem> coupled_;
  std::vector<char> support_fixed_;   // per surface vertex
  Eigen::VectorXd support_x_;
};

}  // namespace palpa::rest
