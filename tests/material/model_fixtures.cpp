// SPDX-License-Identifier: AGPL-3.0-or-later
#include "model_fixtures.hpp"

#include <algorithm>
#include <cmath>

#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::material::test {

std::vector<ModelCase> all_model_cases() {
  const double e = 12e3;
  const double nu = 0.45;
  const ElasticConstants lame = lame_from_young(e, nu);
  const double k = lame.bulk();
  const double d1 = 2.0 / k;  // K = 2/D1
  const ElasticConstants stv = lame_from_young(e, 0.3);
  // Ogden: μ0 = ½ Σ μp αp = ½ (3000·2.5 + (−500)(−2)) = 4250
  const double ogden_mu0 = 4250.0;
  const double ogden_lambda = 2.0 * ogden_mu0 * nu / (1.0 - 2.0 * nu);
  // Mooney–Rivlin / Yeoh with μ = 2 (C10 + C01)
  const auto iso = [&](double mu) { return ElasticConstants{mu, k - 2.0 * mu / 3.0}; };

  std::vector<ModelCase> cases;
  cases.push_back({"NeoHookean", [=] { return std::make_unique<NeoHookean>(e, nu); }, lame, 1e-10});
  cases.push_back({"NeoHookeanVolume",
                   [=] { return std::make_unique<NeoHookean>(NeoHookean::with_volume_term(e, nu, 0.4)); },
                   lame, 1e-10});
  cases.push_back({"NeoHookeanIsochoric",
                   [=] {
                     return std::make_unique<IsochoricInvariant>(
                         IsochoricInvariant::neo_hookean(lame.mu / 2.0, d1));
                   },
                   lame, 1e-10});
  cases.push_back({"MooneyRivlin",
                   [=] {
                     return std::make_unique<IsochoricInvariant>(
                         IsochoricInvariant::mooney_rivlin(1500.0, 400.0, d1));
                   },
                   iso(2.0 * 1900.0), 1e-10});
  cases.push_back({"Yeoh",
                   [=] {
                     return std::make_unique<IsochoricInvariant>(
                         IsochoricInvariant::yeoh(1800.0, -150.0, 60.0, d1));
                   },
                   iso(3600.0), 1e-10});
  cases.push_back({"StVK", [=] { return std::make_unique<StVenantKirchhoff>(e, 0.3); }, stv, 1e-10,
                   false});
  cases.push_back({"Corotational", [=] { return std::make_unique<Corotational>(e, 0.3); }, stv,
                   1e-10});
  cases.push_back({"Ogden",
                   [=] {
                     return std::make_unique<Ogden>(std::vector<double>{3000.0, -500.0},
                                                    std::vector<double>{2.5, -2.0}, nu);
                   },
                   ElasticConstants{ogden_mu0, ogden_lambda}, 1e-10});
  // Spline materials approximate their model: a few percent at 10 knots.
  SplineLayout fine;
  fine.f = {0.5, 2.0, 10};
  fine.g = {0.4, 2.5, 10};
  fine.h = {0.6, 1.6, 10};
  cases.push_back({"SplineFromNeoHookean",
                   [=] {
                     return std::make_unique<SplineMaterial>(
                         SplineMaterial::from_model(NeoHookean(e, nu), fine));
                   },
                   lame, 0.05});
  cases.push_back({"SplineFromMooneyRivlin",
                   [=] {
                     return std::make_unique<SplineMaterial>(SplineMaterial::from_model(
                         IsochoricInvariant::mooney_rivlin(1500.0, 400.0, d1), fine));
                   },
                   iso(3800.0), 0.10});
  return cases;
}

Eigen::VectorXd param_scale(const Material& m, double modulus) {
  const Eigen::VectorXd theta = m.params();
  Eigen::VectorXd scale(theta.size());
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const double floor = m.param_info(k).dimension == Dimension::Pressure ? modulus : 1e-3 * std::abs(theta[k]);
    scale[k] = std::max(std::abs(theta[k]), floor);
  }
  return scale;
}

}  // namespace palpa::material::test
