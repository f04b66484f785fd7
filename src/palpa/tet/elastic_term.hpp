// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The elastic energy of a tet body (model.hpp) as a term (solve/term.hpp):
// one element stencil per tet, its four corners, with the element's 12×12
// Hessian (tet_evaluate), PSD-projected as the assembler asks.

#include "palpa/solve/term.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::tet {

// The four corners of tet e into `vertices`; returns 4 (a tet term's stencil).
inline int tet_corners(const ElasticModel& model, Eigen::Index e, int* vertices) {
  for (int a = 0; a < 4; ++a) vertices[a] = model.mesh().T(e, a);
  return 4;
}

class ElasticTerm final : public Term {
 public:
  // model: must outlive the term.
  explicit ElasticTerm(const ElasticModel& model) : model_(&model) {}

  double energy(const VertexState& s) const override { return model_->elastic_energy(s.u); }
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override;

  int stencil_size() const noexcept override { return 4; }
  Eigen::Index num_stencils() const noexcept override { return model_->num_elements(); }
  int stencil(Eigen::Index e, int* vertices) const override { return tet_corners(*model_, e, vertices); }
  bool stencil_hessian(const VertexState& s, Eigen::Index e, PsdProjection projection, double* h) const override;

 private:
  const ElasticModel* model_;
};

}  // namespace palpa::tet
