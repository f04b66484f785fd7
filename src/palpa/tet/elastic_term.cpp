// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/elastic_term.hpp"

#include <cmath>

namespace palpa::tet {

double ElasticTerm::add_gradient(const VertexState& s, Eigen::VectorXd& g) const {
  Eigen::VectorXd ge;
  const double e = model_->elastic_energy(s.u, &ge);
  if (std::isfinite(e)) g += ge;
  return e;
}

bool ElasticTerm::stencil_hessian(const VertexState& s, Eigen::Index e, PsdProjection projection, double* h) const {
  TetResult r;
  if (!tet_evaluate(model_->material_of(e), model_->geometry(e), model_->element_positions(s.u, e),
                    material::EvalOrder::Hessian, projection, r)) {
    return false;
  }
  Eigen::Map<Mat12> out(h);
  out = r.hessian;
  return true;
}

}  // namespace palpa::tet
