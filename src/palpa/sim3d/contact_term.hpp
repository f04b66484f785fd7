// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Penalty contact of a tet body's surface vertices with one rigid obstacle
// (thesis §7.3.4–7.3.5, Appendix A), as a vertex term of the tet systems.
//
// energy(x) detects afresh at x (a line-search trial sees its own contacts);
// prepare(x) commits the contact set of an accepted iterate; the gradient and
// Hessian use the committed features with sliding anchors (exact derivatives
// of the committed energy). Collision-detection time is accumulated for the
// benchmarks and the summary.

#include <atomic>
#include <vector>

#include "palpa/contact/contact.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::sim3d {

class RigidContactTerm final : public tet::VertexTerm {
 public:
  // obstacle: must outlive the term; its pose may change between solves.
  // rest: the body's rest positions (#V×3) [m]; faces: its skin triangles
  // (rows of rest, outward), whose vertices are the ones that can touch.
  // k [N/m]: the spring of a vertex of mean skin area.
  //
  // Springs follow the area each vertex presses with: a vertex's spring is
  // k·A_i/Ā, with A_i its share (a third) of the skin triangles whose three
  // corners are all in contact (its full skin share before it touches, or if
  // none of its triangles is wholly in contact), Ā the mean skin share. So a
  // uniform penetration δ is a uniform pressure 2kδ/Ā, the nodal forces are
  // the consistent loads of that pressure, and a vertex on a sharp rim is not
  // loaded through the sides that do not touch. Areas are rest areas (the
  // pressures are nominal). They change only in update_areas(), which the
  // driver calls between equilibrium solves (re-solving while they change),
  // so that within one Newton solve the energy is one fixed function.
  RigidContactTerm(const contact::Obstacle& obstacle, const Eigen::MatrixX3d& rest, Eigen::MatrixX3i faces,
                   double k);

  double stiffness() const noexcept { return k_; }
  void set_stiffness(double k);
  const contact::Obstacle& obstacle() const noexcept { return *obstacle_; }
  const std::vector<int>& surface() const noexcept { return surface_; }
  const contact::ContactSet& contacts() const noexcept { return committed_; }

  double energy(const Eigen::VectorXd& x) const override;
  double add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void add_hessian(const Eigen::VectorXd& x, bool true_hessian,
                   std::vector<std::pair<int, Eigen::Matrix3d>>& blocks) const override;
  void prepare(const Eigen::VectorXd& x) override;
  bool active() const override { return !committed_.empty(); }

  // Sets each vertex's spring area from the committed contacts (see above)
  // if they change by more than `min_change` (Σ|ΔA_i| over the total spring
  // area); returns that change when applied, else 0 (nothing changed). A
  // small threshold stops a rim vertex that touches in one solve and not in
  // the next from cycling the re-solves forever.
  double update_areas(double min_change = 0.0);
  // Restores spring areas saved from spring_area() (one per body vertex,
  // each > 0 on the skin); palpa::Error (Input) otherwise.
  void set_areas(const std::vector<double>& areas);

  // Contact force on every body vertex at positions x (3×N) [N], and the
  // wrench on the obstacle about `about` [m].
  Eigen::Matrix3Xd vertex_forces(const Eigen::VectorXd& x) const;
  // Contact pressure per body vertex at x [Pa]: |f_i| over its contact area
  // (2kδ_i/Ā), 0 off contact.
  Eigen::VectorXd pressures(const Eigen::VectorXd& x) const;
  // The mean skin vertex area Ā [m²] and each vertex's current spring area.
  double mean_area() const noexcept { return mean_area_; }
  const std::vector<double>& spring_area() const noexcept { return area_; }
  contact::Wrench obstacle_wrench(const Eigen::VectorXd& x, const Eigen::Vector3d& about) const;

  // Seconds spent in collision detection since construction (or reset).
  double detection_seconds() const noexcept { return detection_ns_.load() * 1e-9; }
  std::int64_t detections() const noexcept { return detections_.load(); }
  void reset_timers() noexcept {
    detection_ns_ = 0;
    detections_ = 0;
  }

 private:
  const contact::Obstacle* obstacle_;
  std::vector<int> surface_;
  Eigen::MatrixX3i faces_;
  Eigen::VectorXd face_area_;   // per skin triangle, at rest [m²]
  Eigen::VectorXd skin_area_;   // per vertex, full skin share at rest [m²]
  double mean_area_ = 0.0;
  std::vector<double> area_;    // per vertex, current spring area [m²]
  std::vector<double> scale_;   // area_/Ā
  double k_;
  contact::ContactSet committed_;
  mutable std::atomic<std::int64_t> detection_ns_{0};
  mutable std::atomic<std::int64_t> detections_{0};
};

}  // namespace palpa::sim3d
