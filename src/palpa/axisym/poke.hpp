// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Indentation of a layer on a rigid base by a rigid flat-ended cylindrical
// punch, in axisymmetry (thesis ch. 4–5): the force–indentation curve, and the
// sensitivity of every force sample to every material parameter (thesis §6.2).
//
// Boundary conditions (rest coordinates): base z = −D bonded (u = 0); axis r = 0
// has u_r = 0; the top-surface nodes under the flat face of the punch
// (r <= a − ρ) have u_z = −d and, for Stick contact, u_r = 0 (thesis §5.3); for
// Frictionless contact u_r is free (§5.2). The outer rim r = R is free.
// The punch is also a rigid solid (punch.hpp): every other top-surface node is
// kept out of it by a penalty on its penetration depth, detected at every
// energy evaluation (so at every Newton iterate and line-search trial), acting
// along the punch's normal (no friction). The penalty stiffness per unit area is
// penalty_factor · μ0 / h_rim (μ0: small-strain shear modulus, h_rim: the rim
// cell size, mesh.rim_cell_size; the corner cell size for compression), so penetrations stay ~1/penalty_factor of the local strain times
// h_rim; the largest is reported per depth.
//
// Force: the total downward force of the punch on the layer [N], full circle:
// minus the reactions of the prescribed u_z plus the penalty forces' vertical
// components (thesis 5.5).
//
// Compression (PokeTest::Compression): a whole cylindrical sample of radius R
// and height H (mesh.hpp, make_cylinder_mesh) between two rigid plates; the top
// platen moves down by d. Stick (= bonded platens): top nodes u = (0, −d), base
// nodes u = 0; Frictionless: top nodes u_z = −d and base nodes u_z = 0 with u_r
// free. The side wall r = R is free, but kept out of both platens (the solid
// half-spaces above the top platen and below the base, punch.hpp) by the same
// penalty, so a bonded sample's bulging wall can fold onto them under large
// compression. The force is the total downward force on the top platen, full
// circle (reactions of the top nodes plus penalty forces of the wall nodes on
// the top platen). Frictionless platens give homogeneous uniaxial compression
// until that state turns unstable (Biot's surface instability of the side
// wall, near 55% for neo-Hookean materials); past it the wall creases.
//
// Sensitivities: at the equilibrium u*(θ), dF/dθ = ∂F/∂θ − λᵀ ∂g_F/∂θ with
// K_FF λ = ∂F/∂u_F (the true Hessian): one back-solve per depth for all
// parameters.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "palpa/axisym/element.hpp"
#include "palpa/axisym/mesh.hpp"
#include "palpa/axisym/punch.hpp"
#include "palpa/material/material.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/solve/parametric_system.hpp"
#include "palpa/solve/system.hpp"

namespace palpa::axisym {

enum class PunchContact { Stick, Frictionless };
std::string_view to_string(PunchContact c) noexcept;
// "stick" | "frictionless"; throws palpa::Error (Input) otherwise.
PunchContact parse_punch_contact(std::string_view name);

// Indentation: a punch of radius a pressed into a layer (thickness D) on a
// rigid base. Compression: a whole cylinder (radius R, height H) between two
// plates, the "punch" covering all of its top.
enum class PokeTest { Indentation, Compression };
std::string_view to_string(PokeTest t) noexcept;
// "indentation" | "compression"; throws palpa::Error (Input) otherwise.
PokeTest parse_poke_test(std::string_view name);

// Platens of a compression test: "bonded" (PunchContact::Stick) |
// "frictionless"; throws palpa::Error (Input) otherwise.
PunchContact parse_platen_contact(std::string_view name);
// "bonded" | "frictionless".
std::string_view platen_contact_name(PunchContact c) noexcept;

struct PokeSetup {
  // Indentation: a, D, R (0 = default). Compression: punch_radius = sample
  // radius R (or outer_radius, see make_cylinder_mesh), thickness = height H.
  LayerGeometry geometry;
  PokeTest test = PokeTest::Indentation;
  int mesh_level = 2;              // 0 coarse … 7 very fine
  PunchContact contact = PunchContact::Stick;
  ElementFormulation element = ElementFormulation::FBar;  // see element.hpp
  // F-bar stabilization modulus as a multiple of the material's small-strain
  // shear modulus μ0 at construction. Like the contact penalty it is a
  // property of the discretization, fixed for the model's lifetime (a fit that
  // changes the parameters keeps it), so sensitivities stay exact.
  double fbar_stabilization = 1.0;
  double fillet_radius = 0.0;      // ρ [m], rounds the punch rim; 0 <= ρ < a (0 for compression)
  double penalty_factor = 1e3;     // contact stiffness, see above
  // Richardson extrapolation over two nested meshes, for indentation by a
  // sharp punch (fillet 0). Its rim is a stress singularity, so the force of
  // these elements converges at first order in the cell size there:
  // F_L = F + c h_L + O(h_L²). Solving the mesh one level coarser beside it
  // (every cell split 2 × 2 makes level L, so h_L = h_{L−1}/2) and reporting
  // 2 F_L − F_{L−1} cancels the first-order term at a quarter more work
  // (level 2: from +1.2% to −0.2% of the layer's analytic stiffness); the
  // sensitivities are the same combination, so they stay exact. Not done
  // where convergence is not first order, so the combination would
  // overshoot: a rounded rim (smooth contact edge, faster and irregular
  // convergence once the fillet is resolved) and compression tests (the
  // weaker corner singularity of a bonded sample converges at about second
  // order; frictionless platens are exact on any mesh). Level 0 has no
  // coarser mesh.
  bool extrapolate = true;
};

// Whether a simulator of this set-up extrapolates (PokeSetup::extrapolate, an
// indentation by a sharp punch, mesh_level >= 1).
bool extrapolates(const PokeSetup& setup) noexcept;

// The layer and punch at one depth, over the free DOFs (x: #free [m]).
// Energy: elastic [J] + contact penalty [J].
class PokeModel final : public System, public ParametricSystem {
 public:
  PokeModel(const material::Material& material, const PokeSetup& setup);
  ~PokeModel() override;

  const AxisymMesh& mesh() const noexcept { return mesh_; }
  const PokeSetup& setup() const noexcept { return setup_; }
  const material::Material& material() const noexcept { return *material_; }
  // Replaces the material parameters (same model). Validated by the material.
  void set_material_params(const Eigen::VectorXd& theta);

  // The punch depth d [m] (prescribed u_z = −d on the face nodes); for
  // compression the travel of the top platen.
  void set_depth(double depth);
  double depth() const noexcept { return punch_.depth; }

  // Newton uses PSD-projected element Hessians; sensitivities need the true one.
  void set_true_hessian(bool on) noexcept { true_hessian_ = on; }

  // System
  Eigen::Index num_dofs() const override { return static_cast<Eigen::Index>(free_dofs_.size()); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  // Element Hessians projected to PSD and the contact's k n nᵀ (Newton's
  // stand-in where the true Hessian is not positive definite).
  bool projected_hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  // The punch's contact is checked inside every call (no committed anchors).
  bool stateless() const noexcept override { return true; }

  // ParametricSystem: ∂g/∂θ over the free DOFs (#free × p).
  Eigen::Index num_params() const override;
  void gradient_param_jacobian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& J) const override;
  // (∂g/∂θ)ᵀ λ (p) for a λ over the free DOFs, without forming ∂g/∂θ: what
  // an adjoint sensitivity needs.
  Eigen::VectorXd gradient_param_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& lambda) const;

  // All nodal displacements (#N × 2, (u_r, u_z) [m]) for free DOFs x at the
  // current depth.
  Eigen::MatrixX2d displacements(const Eigen::VectorXd& x) const;

  // F(x): downward punch (top platen) force [N] (see above).
  double punch_force(const Eigen::VectorXd& x) const;
  // ∂F/∂x (#free) and ∂F/∂θ (p) at x, with the true Hessian terms.
  void punch_force_derivatives(const Eigen::VectorXd& x, Eigen::VectorXd& dfdx,
                               Eigen::VectorXd& dfdtheta) const;

  struct Diagnostics {
    double max_penetration = 0.0;  // largest penetration into the punch (platens) [m]
    double min_jacobian = 0.0;     // smallest det F over all Gauss points
    int contact_nodes = 0;         // free surface nodes touching the punch (platens)
  };
  Diagnostics diagnostics(const Eigen::VectorXd& x) const;

  // ∂g/∂d at fixed free DOFs x: how the out-of-balance forces change as the
  // punch (top platen) and the face nodes move down [N/m], by a central
  // difference of step eps [m] in the depth (g is smooth in d except where a
  // node's contact starts or ends within ±eps). The path of equilibria x(d)
  // has the tangent dx/dd = −K⁻¹ ∂g/∂d (K: the Hessian over the free DOFs).
  // Leaves the depth as it was. Returns false (dg unspecified) where x at
  // depth ± eps inverts a cell.
  bool gradient_depth_derivative(const Eigen::VectorXd& x, double eps, Eigen::VectorXd& dg);

  // Which contact checks (surface nodes against the punch or a platen) are
  // active, φ < 0, at x and the current depth: one flag per check.
  std::vector<char> contact_set(const Eigen::VectorXd& x) const;
  // For a predicted x at the current depth: moves every node that is inside an
  // obstacle but was not in contact in `previous` (contact_set of the last
  // equilibrium) back along its normal (free components only), to
  // 1/penalty_factor of its penetration. A node newly caught by the punch then
  // starts near its equilibrium (a penetration of ~1/penalty_factor of the
  // strain times the cell) instead of deep inside, where the stiff penalty
  // would dominate the residual, and still inside, so that the first Hessian
  // holds its penalty (placed exactly on the surface, the first Newton step
  // drives it deep into the punch and the line search cuts that step to
  // 1/128–1/256: measured on the foam curve). Returns the number of nodes moved.
  int separate_new_contacts(Eigen::VectorXd& x, const std::vector<char>& previous) const;

  // Per-node contact pressure on the top surface [Pa]: punch force on the node
  // (reaction or penalty) over its ring area 2π r ℓ; #N (0 away from the top).
  // Compression: also the base platen's push on the base nodes, and the penalty
  // pressure of side-wall nodes folded onto either platen.
  Eigen::VectorXd contact_pressure(const Eigen::VectorXd& x) const;

  // Per-element output fields (element.hpp), in element order.
  std::vector<ElementState> element_states(const Eigen::VectorXd& x) const;

  // Top-surface nodes whose u_z is prescribed (under the flat face).
  const std::vector<int>& face_nodes() const noexcept { return face_nodes_; }

  // Rounding floors of the energy [J] and of a gradient entry [N]: Ψ near rest
  // is a sum of O(μδ) terms cancelling to O(μδ²), so each Gauss point carries an
  // error of about μ·ε whatever the strain; summed over a cell of volume V and
  // size h that is μ·ε·V (energy) and μ·ε·V/h (force). Newton's tolerances
  // must stay above these.
  double energy_noise_floor() const noexcept { return energy_noise_floor_; }
  double gradient_noise_floor() const noexcept { return gradient_noise_floor_; }

 private:
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const;
  // The true Hessian, or (true_hessian false) the PSD-projected one.
  void assemble_hessian(const Eigen::VectorXd& x, bool true_hessian, Eigen::SparseMatrix<double>& H) const;
  Eigen::VectorXd full_displacement(const Eigen::VectorXd& x) const;
  // Elastic gradient over all DOFs (2 per node) at the full displacement u.
  Eigen::VectorXd full_elastic_gradient(const Eigen::VectorXd& u) const;
  Vec8 element_dofs(const Eigen::VectorXd& u, Eigen::Index e) const;

  // A free node kept out of a rigid obstacle by the penalty ½ k φ².
  enum class Obstacle { Punch, TopPlaten, BasePlaten };
  struct ContactCheck {
    int node = 0;
    Obstacle obstacle = Obstacle::Punch;
    double stiffness = 0.0;  // k = penalty per area × the node's surface share [N/m]
  };
  PunchDistance distance(const ContactCheck& c, const Eigen::VectorXd& u) const;
  // Whether the obstacle is the body whose force F is (punch, top platen).
  static bool pushes_down(Obstacle o) noexcept { return o != Obstacle::BasePlaten; }

  std::unique_ptr<material::Material> material_;
  PokeSetup setup_;
  AxisymMesh mesh_;
  PunchShape punch_;
  std::vector<QuadGeometry> geometry_;
  std::vector<int> free_dofs_;        // free index -> full DOF
  std::vector<int> full_to_free_;     // full DOF -> free index or −1
  std::vector<int> face_nodes_;       // prescribed u_z = −d
  std::vector<int> platen_base_nodes_;  // compression: base nodes on the base platen
  std::vector<ContactCheck> contacts_;  // nodes checked against the punch or platens
  std::vector<double> ring_area_;     // per node: its share of the top (and base) surface, 2π r ℓ [m^2]
  double penalty_per_area_ = 0.0;     // [Pa/m]
  ElementOptions element_;            // formulation and stabilization modulus
  double energy_noise_floor_ = 0.0;
  double gradient_noise_floor_ = 0.0;
  bool true_hessian_ = false;
  // Hessian pattern over free DOFs (lower triangle) and, per element, the slot
  // of each of its 64 entries in the value array (−1: not assembled).
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 64>> element_slots_;
  std::vector<std::array<int, 3>> contact_slots_;  // per contact check: (rr, zr, zz) slots
};

struct PokeOptions {
  double max_depth = 0.0;        // [m], below 90% of the thickness (height)
  int steps = 20;                // equal depth increments up to max_depth
  bool sensitivities = false;    // dF/dθ per depth
  int max_step_cuts = 10;        // halvings of a depth increment that fails
  // When > 0: a depth whose Newton iterations fail while the last
  // equilibrium's smallest det F is below this gives up at once instead of
  // halving the step (a depth whose every guess inverts a cell still halves).
  // The cells at the punch rim are then crushed to that fraction of their
  // volume and the mesh cannot follow the material much deeper (for curves
  // that are shown, not fitted; 0 = always halve).
  double give_up_below_jacobian = 0.0;
  // Also start each depth from the equilibrium the previous run() of this
  // simulator reached there (same depth schedule), where that is closer to
  // equilibrium than the path predictor (smaller ‖g‖∞). For a fit, whose
  // material changes little between runs, this saves Newton iterations.
  bool warm_start = false;
  // Tolerances default to the problem's scale; chord_ratio 0 means 1000 here
  // (chord steps on), a negative value turns chord steps off.
  NewtonOptions newton;
};

struct PokeSample {
  double depth = 0.0;           // [m]
  double force = 0.0;           // [N]
  int newton_iterations = 0;    // over all sub-steps to this depth
  int substeps = 1;             // 1 unless the increment had to be cut
  double residual = 0.0;        // final ‖g‖∞ [N]
  double max_penetration = 0.0; // [m]
  double min_jacobian = 0.0;    // smallest det F
  int contact_nodes = 0;        // free surface nodes on the punch
  Eigen::VectorXd dforce_dparams;  // p entries [N per unit θ] if requested
  // With extrapolation (PokeSetup::extrapolate): force minus the force of the
  // mesh at mesh_level, F_L − F_{L−1}, the estimated discretization error of
  // that mesh [N]; 0 without. Newton iterations count both meshes; substeps,
  // residual and the diagnostics are those of the mesh at mesh_level.
  double mesh_correction = 0.0;
};

struct PokeCurve {
  std::vector<PokeSample> samples;  // depth 0 first (force 0), then each step
  int newton_iterations = 0;
  std::int64_t factorizations = 0;
  std::int64_t analyses = 0;
};

// The equilibria (free DOFs) a run() reached at each step depth, from depth 0,
// and its deepest depth [m]; empty after a run that failed or was not warm
// started (PokeOptions::warm_start).
struct WarmStart {
  double max_depth = 0.0;
  std::vector<Eigen::VectorXd> solutions;
  // With extrapolation: those of the mesh one level coarser.
  std::vector<Eigen::VectorXd> coarse_solutions;
};

// Runs depth continuation on one model (with extrapolation: on two, the
// coarser mesh solved at each depth just before the finer), reusing their
// Hessian patterns and symbolic factorizations across depths and across run()
// calls (a fit calls run() once per parameter update).
class PokeSimulator {
 public:
  PokeSimulator(const material::Material& material, const PokeSetup& setup);
  ~PokeSimulator();

  // The model on the mesh at setup.mesh_level (with extrapolation, the finer
  // of the two): its mesh, fields and diagnostics are what run() reports
  // beside the extrapolated force. Change the material through
  // set_material_params, which changes both meshes' models.
  PokeModel& model() noexcept { return *model_; }
  const PokeModel& model() const noexcept { return *model_; }
  // Whether run() extrapolates (extrapolates(setup)).
  bool extrapolates() const noexcept { return coarse_ != nullptr; }
  // Replaces the material parameters (same model) of every mesh's model.
  void set_material_params(const Eigen::VectorXd& theta);

  // Called after each depth converged with the model, its free DOFs and the sample.
  using DepthCallback = std::function<void(const PokeModel&, const Eigen::VectorXd&, const PokeSample&)>;

  // Throws palpa::Error (Input) for bad options, (Solver) with diagnostics when a
  // depth does not converge even after max_step_cuts halvings, (Interrupted)
  // on Ctrl-C.
  PokeCurve run(const PokeOptions& options, const DepthCallback& on_depth = {});

  // What the next warm-started run() starts from; a fit's checkpoint saves
  // it, so that a resumed fit repeats the uninterrupted one bit for bit.
  const WarmStart& warm_start() const noexcept { return warm_; }
  void set_warm_start(WarmStart w) { warm_ = std::move(w); }

 private:
  std::unique_ptr<PokeModel> model_;
  NewtonSolver solver_;
  std::unique_ptr<PokeModel> coarse_;  // extrapolation: the mesh at mesh_level − 1
  NewtonSolver coarse_solver_;
  WarmStart warm_;
};

}  // namespace palpa::axisym
