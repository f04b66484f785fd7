#pragma once
// A body resting on a support (thesis §7.3): the soft layer on its rigid core
// (body/core_system.hpp) under gravity and an external wrench, pressed onto a
// rigid, fixed, closed support surface by penalty contact with sliding
// anchors, solved for static equilibrium; then the contact pressures on the
// body and — by the reverse query, the support's vertices against the
// deformed body surface — on the support (bidirectional, Fig. 7.4).
//
// The body starts slightly above the support and falls onto it: while nothing
// touches, the Newton system is K + αM (§7.3.4). With an automatic penalty
// stiffness (a target maximum penetration, 0.3 mm by default as in the thesis)
// k starts from the load shared by a tenth of the body's surface vertices,
// and the equilibrium is solved again with k scaled by depth/target until the
// deepest penetration is within 15% of the target.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "palpa/body/core_system.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/io/vtu.hpp"
#include "palpa/sim3d/contact_term.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::rest {

struct RestBody {
  TetMesh mesh;                             // the layer, positively oriented [m]
  std::vector<int> attached;                // vertices on the core surface
  std::vector<tet::BodyMaterial> materials;
  Eigen::VectorXi element_material;         // empty: all materials[0]
};

// The body's skin: the boundary faces of the layer with no corner on the core
// (outward, rows of the tet mesh's V).
Eigen::MatrixX3i skin_faces(const TetMesh& mesh, const std::vector<int>& attached);
// The skin as a closed surface of its own (vertices renumbered).
SurfaceMesh body_skin(const RestBody& body);

struct RestOptions {
  body::CoreSpec core;  // attached is taken from the body; centre: see below
  bool core_centre_given = false;  // else c0 = the mean of the attached vertices
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  double target_penetration = 3e-4;  // [m]
  double stiffness = 0.0;            // k [N/m]; > 0 fixes it (no automatic rule)
  LineSearchKind line_search = LineSearchKind::BacktrackingThenBrent;
  int max_iterations = 300;
  double force_tolerance = 0.0;      // [N]; 0: 1e-6 of the load over the surface vertices
  double regularization = 1e4;       // α [1/s²] before landing
  // Spring areas follow the contact between solves (sim3d/contact_term.hpp).
  // Off: they stay as they are, so the equilibrium is one smooth function of
  // the support's shape (shape optimization).
  bool update_areas = true;
  std::string support_name = "support";
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
  int contacts = 0;
  int support_contacts = 0;
  int newton_iterations = 0;
  int solves = 0;
  double seconds = 0.0;
  double detection_seconds = 0.0;
  double residual = 0.0;             // ‖g‖∞ [N]
  double min_det_f = 0.0;
  Eigen::VectorXd body_pressure;     // per body vertex [Pa] (0 off contact)
  Eigen::VectorXd support_pressure;  // per support vertex [Pa]
  std::string message;
};

// A support vertex inside the deformed body (the reverse query): its closest
// point on the body's boundary, whose `vertices` are rows of the body's tet
// mesh.
struct ReverseContact {
  int support_vertex = -1;
  contact::ClosestPoint closest;
};

// Everything a solve starts from: with the same body and support it restores
// a simulation exactly (a warm start, a checkpoint).
struct RestState {
  Eigen::VectorXd x;                   // CoreSystem DOFs
  body::CoreSystem::Committed core;    // committed core pose
  std::vector<double> spring_areas;    // per body vertex [m²]
  double stiffness = 0.0;              // k [N/m]
};

class RestSimulation {
 public:
  // support: closed surface in world coordinates. Throws palpa::Error (Input)
  // for a support that is not a closed, manifold, outward surface, a core
  // without attached vertices or with nothing free, and a body that starts
  // inside the support (it must start above it).
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
  const contact::Obstacle& support() const noexcept { return *support_; }
  const Eigen::VectorXd& dofs() const noexcept { return x_; }
  const sim3d::RigidContactTerm& contact_term() const noexcept { return *term_; }
  NewtonSolver& newton() noexcept { return *newton_; }
  const std::vector<int>& surface_vertices() const noexcept { return surface_; }
  const Eigen::MatrixX3i& boundary_faces() const noexcept { return boundary_faces_; }
  const Eigen::VectorXd& skin_area() const noexcept { return body_area_; }  // per body vertex [m²]

  RestState state() const;
  // Throws palpa::Error (Input) for a state of another body.
  void restore(const RestState& s);
  // Moves the support's vertices (world [m], same triangles and count); the
  // next solve starts from the current state.
  void set_support_vertices(const Eigen::MatrixX3d& V);
  // Keeps k and the spring areas as they are in later solves (no automatic
  // correction, no area updates): the equilibrium becomes one smooth function
  // of the support's shape.
  void freeze_contact_model() noexcept {
    automatic_ = false;
    options_.update_areas = false;
  }
  // The support's vertices inside the deformed body at the current state,
  // against its skin (not its core shells).
  std::vector<ReverseContact> reverse_contacts() const;
  const Eigen::MatrixX3i& surface_faces() const noexcept { return surface_faces_; }  // outer skin, tet-mesh rows

  // The deformed body (tets, point data displacement_m, contact_force_N,
  // pressure_Pa; cell data von_mises_stress_Pa) and the support with
  // pressure_Pa, for the result r.
  UnstructuredGrid body_grid(const RestResult& r) const;
  UnstructuredGrid support_grid(const RestResult& r) const;
  // The deformed outer skin with pressure_Pa (tet-mesh vertex numbering kept).
  SurfaceMesh deformed_skin() const;

 private:
  RestBody body_;
  RestOptions options_;
  std::unique_ptr<tet::ElasticModel> model_;
  std::unique_ptr<body::CoreSystem> system_;
  std::unique_ptr<contact::Obstacle> support_;
  std::unique_ptr<sim3d::RigidContactTerm> term_;
  std::unique_ptr<NewtonSolver> newton_;
  std::vector<int> surface_;          // body boundary vertices not attached to the core
  Eigen::MatrixX3i surface_faces_;    // boundary faces without attached corners
  Eigen::MatrixX3i boundary_faces_;   // the whole boundary (skin and core shells)
  Eigen::VectorXd body_area_;         // per vertex [m²]
  Eigen::VectorXd support_area_;      // per support vertex [m²]
  double mean_area_ = 0.0;            // mean skin vertex area Ā [m²]
  Eigen::VectorXd x_;
  bool automatic_ = true;
};

}  // namespace palpa::rest
