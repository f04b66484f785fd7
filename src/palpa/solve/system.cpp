#include "palpa/solve/system.hpp"

#include "palpa/solve/parametric_system.hpp"

namespace palpa {

System::~System() = default;

double System::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  gradient(x, g);
  return energy(x);
}

void System::prepare(const Eigen::VectorXd& /*x*/) {}

ParametricSystem::~ParametricSystem() = default;

Eigen::MatrixXd solution_param_jacobian(const SymmetricFactorization& hessian_factor,
                                        const Eigen::SparseMatrix<double>& dg_dtheta) {
  const Eigen::MatrixXd rhs = -Eigen::MatrixXd(dg_dtheta);
  return hessian_factor.solve(rhs);
}

}  // namespace palpa
