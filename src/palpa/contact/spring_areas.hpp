// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The area each skin vertex presses with, for node-to-surface penalty contact:
// a vertex's spring is k·A_i/Ā, with A_i its share (a third) of the skin
// triangles whose three corners are all in contact (its full skin share before
// it touches, or if none of its triangles is wholly in contact), Ā the mean
// skin share. So a uniform penetration δ is a uniform pressure 2kδ/Ā, the
// nodal forces are the consistent loads of that pressure, and a vertex on a
// sharp rim is not loaded through the sides that do not touch. Areas are rest
// areas (the pressures are nominal). They change only in update(), which a
// driver calls between equilibrium solves (re-solving while they change), so
// that within one Newton solve the energy is one fixed function.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>


namespace palpa::contact {

class SpringAreas {
 public:
  // rest: the body's rest positions (#V×3) [m]; faces: its skin triangles
  // (rows of rest). name: used in error messages. Throws palpa::Error (Input)
  // when there are no skin faces.
  SpringAreas(const Eigen::MatrixX3d& rest, Eigen::MatrixX3i faces, std::string name);

  // The skin's vertices (sorted): the points that can touch.
  const std::vector<int>& surface() const noexcept { return surface_; }
  const Eigen::MatrixX3i& faces() const noexcept { return faces_; }
  // The mean skin vertex area Ā [m²].
  double mean_area() const noexcept { return mean_area_; }
  // Per body vertex: its spring area A_i [m²] and its spring factor A_i/Ā.
  const std::vector<double>& areas() const noexcept { return area_; }
  const std::vector<double>& scale() const noexcept { return scale_; }
  // Per body vertex: its full share of the skin (a third of its skin
  // triangles' rest areas; 0 off the skin) [m²].
  const Eigen::VectorXd& skin_areas() const noexcept { return skin_area_; }

  // Sets the areas from the vertices in contact (body vertices) if they
  // change by more than `min_change` (Σ|ΔA_i| over the area in contact);
  // returns that change when applied, else 0. A small threshold stops a rim
  // vertex that touches in one solve and not in the next from cycling the
  // re-solves forever.
  double update(std::span<const int> touching_vertices, double min_change = 0.0);
  // Restores areas saved from areas() (one per body vertex, each > 0 on the
  // skin); palpa::Error (Input) otherwise.
  void set(const std::vector<double>& areas);

 private:
  void rescale();

  std::string name_;
  Eigen::MatrixX3i faces_;
  std::vector<int> surface_;
  Eigen::VectorXd face_area_;  // per skin triangle, at rest [m²]
  Eigen::VectorXd skin_area_;  // per vertex, full skin share at rest [m²]
  double mean_area_ = 0.0;
  std::vector<double> area_;   // per vertex, current spring area [m²]
  std::vector<double> scale_;  // area_/Ā
};

}  // namespace palpa::contact
