// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A hyperelastic body meshed with linear tets (thesis §7.3.3): per-element
// materials, mass, gravity, and the assembly of energy, gradient and Hessian.
//
// DOFs. The model works on the full nodal displacement u (3N, u = x − X,
// vertex-major: u[3v + c]). Which DOFs are free, and what other energies act
// on the vertices (contact), is the business of the systems built on it
// (system.hpp); its energy and gradient here are parallel (TBB), its element
// Hessians are the ElasticTerm's stencils (elastic_term.hpp).
//
// Units: positions [m], density [kg/m³], energies [J], forces [N].

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "palpa/geometry/mesh.hpp"
#include "palpa/material/material.hpp"
#include "palpa/tet/element.hpp"

namespace palpa::tet {

// The element of the body's energy: the linear tet (constant F per tet), or
// the linear tet with nodally averaged volume change (nodal_pressure.hpp),
// which does not lock as ν → 0.5, optionally stabilized by keeping a share β
// of each tet's own volume change. The systems built on a model read it when
// they are built.
enum class TetElement { Linear, NodalPressure };

// The stabilization β of the nodal-pressure tet when a scene names none: the
// smallest share that converged on every shipped scan (pure averaging, β 0,
// does not on the foot's; β 0.05 takes 77 Newton iterations there, β 0.1 31).
inline constexpr double kDefaultStabilization = 0.1;

// An element as scene files name it: the element and its stabilization β.
// A body's default is the stabilized nodal-pressure tet: tissue is nearly
// incompressible and the linear tet locks (at ν 0.45 the seated body's peak
// comes out 24% high, a Hertz force 24% stiff at ν 0.49).
struct ElementChoice {
  TetElement element = TetElement::NodalPressure;
  double stabilization = kDefaultStabilization;
};

// One material of the body, with its mass density.
struct BodyMaterial {
  std::shared_ptr<const material::Material> material;
  double density = 1000.0;  // ρ [kg/m³], ≥ 0
};

class ElasticModel {
 public:
  // mesh: a checked, positively oriented tet mesh (prepare_tet_mesh).
  // element_material: #T indices into `materials` (empty: all use materials[0]).
  // Throws palpa::Error (Input) for an index out of range, a missing material
  // or a negative or non-finite density.
  ElasticModel(TetMesh mesh, std::vector<BodyMaterial> materials,
               Eigen::VectorXi element_material = {});

  const TetMesh& mesh() const noexcept { return mesh_; }
  Eigen::Index num_vertices() const noexcept { return mesh_.V.rows(); }
  Eigen::Index num_elements() const noexcept { return mesh_.T.rows(); }
  Eigen::Index num_dofs() const noexcept { return 3 * mesh_.V.rows(); }
  const std::vector<BodyMaterial>& materials() const noexcept { return materials_; }
  const Eigen::VectorXi& element_material() const noexcept { return element_material_; }
  const material::Material& material_of(Eigen::Index e) const {
    return *materials_[static_cast<std::size_t>(element_material_[e])].material;
  }
  const TetGeometry& geometry(Eigen::Index e) const { return geometry_[static_cast<std::size_t>(e)]; }
  TetElement element() const noexcept { return element_; }
  // β in [0, 1): the share of the volumetric energy left on each tet's own
  // J with NodalPressure (0: pure nodal averaging). Throws palpa::Error
  // (Input) for β outside [0, 1) or β > 0 with the linear tet.
  void set_element(TetElement element, double stabilization = 0.0);
  void set_element(const ElementChoice& c) { set_element(c.element, c.stabilization); }
  double stabilization() const noexcept { return stabilization_; }

  // Lumped mass per vertex (ρV/4 from each tet) [kg], N.
  const Eigen::VectorXd& lumped_mass() const noexcept { return lumped_mass_; }
  double total_mass() const noexcept { return lumped_mass_.sum(); }
  // Consistent mass matrix (3N×3N, lower triangle): ρV/20 (1 + δ_ab) I₃ per tet.
  Eigen::SparseMatrix<double> consistent_mass() const;

  // Deformed corners of element e for displacement u.
  Mat34 element_positions(const Eigen::VectorXd& u, Eigen::Index e) const;

  // Elastic energy [J] at u; +infinity when an element is inverted. When g is
  // given it is set to ∂E/∂u (3N) [N] (left unspecified for +infinity).
  double elastic_energy(const Eigen::VectorXd& u, Eigen::VectorXd* g = nullptr) const;

  // ∂g/∂θ for the parameters of materials[k]: 3N × p_k (dense).
  Eigen::MatrixXd gradient_param_jacobian(const Eigen::VectorXd& u, std::size_t k) const;

  // Potential of a uniform gravitational field g [m/s²] (lumped masses, which
  // is exact for linear elements): −Σ_v m_v g·u_v [J]; its gradient is the
  // constant vector returned by gravity_gradient (3N).
  Eigen::VectorXd gravity_gradient(const Eigen::Vector3d& gravity) const;

  // Per element: Cauchy stress (rows: σxx σyy σzz σyz σxz σxy) [Pa] and its von
  // Mises value, at u. An inverted element (det F ≤ 0), where the stress is
  // undefined, gets 0: its det F says what happened there. With the
  // nodal-pressure element, the averaged share of the pressure is the mean
  // of the tet's corners' patch pressures (the stress whose divergence the
  // element's forces are).
  Eigen::MatrixXd cauchy_stress(const Eigen::VectorXd& u) const;  // #T×6
  static Eigen::VectorXd von_mises(const Eigen::MatrixXd& stress6);

  // Smallest det F over the elements at u.
  double min_jacobian(const Eigen::VectorXd& u) const;

  // Replaces the rest positions (V: #V×3 [m], same rows as mesh().V) and
  // recomputes the element geometry and the lumped masses; topology, materials
  // and densities are kept. Throws palpa::Error (Input) for a wrong row count,
  // and (Solver) for a non-finite position or a tet made inverted or flat
  // (volume ≤ 0, named with its volume) — then the model is left unchanged.
  // Not to be called while another thread evaluates the model. Systems built
  // on the model keep what they derived from the masses (gravity, dynamics)
  // and must be rebuilt.
  void set_rest_positions(const Eigen::MatrixX3d& V);

  // Shape derivative of the elastic forces, for shape optimization by the
  // adjoint method: ∂/∂X [ zᵀ ∂E/∂u ] with the DEFORMED positions x = X + u
  // held fixed (X the rest positions, mesh().V). u: 3N displacement [m],
  // z: 3N (an adjoint vector), both vertex-major; returns #V×3 [N/m × unit of
  // z], row v the derivative with respect to X_v. At fixed u instead (x moving
  // with X), add the Hessian times z (vertex-major, reshaped) to it. Uses the
  // true (unprojected) tangent. Throws palpa::Error (Internal) at an inverted
  // element.
  Eigen::MatrixX3d rest_gradient_product(const Eigen::VectorXd& u, const Eigen::VectorXd& z) const;

 private:
  // Element geometry and lumped masses for rest positions V into geometry and
  // lumped_mass (resized). Returns the first tet whose volume is not a finite
  // positive number (its geometry is then geometry[e]), or −1.
  Eigen::Index compute_rest_data(const Eigen::MatrixX3d& V, std::vector<TetGeometry>& geometry,
                                 Eigen::VectorXd& lumped_mass) const;

  TetMesh mesh_;
  std::vector<BodyMaterial> materials_;
  Eigen::VectorXi element_material_;
  std::vector<TetGeometry> geometry_;
  Eigen::VectorXd lumped_mass_;
  TetElement element_ = TetElement::Linear;
  double stabilization_ = 0.0;
};

}  // namespace palpa::tet
