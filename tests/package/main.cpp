// SPDX-License-Identifier: AGPL-3.0-or-later
// Uses an installed palpa through palpa::palpa: the generated version header,
// units, a material's stress in a homogeneous test and a CHOLMOD solve (solve
// links CHOLMOD privately, so this checks that the package brings it).
// Prints each failed check and exits with 1 if any failed.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string_view>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/core/units.hpp"
#include "palpa/core/version.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/models.hpp"
#include "palpa/solve/sparse_cholesky.hpp"

namespace {

int failures = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

bool close(double a, double b, double rel) { return std::abs(a - b) <= rel * std::abs(b); }

void check_version() {
  check(std::string_view(palpa::kVersion) == PALPA_EXPECTED_VERSION,
        "palpa::kVersion matches the version of the CMake package");
}

void check_units() {
  const palpa::ErrorContext where;
  check(close(palpa::parse_quantity("10 kPa", palpa::Dimension::Pressure, where), 1.0e4, 1e-12),
        "\"10 kPa\" is 10000 Pa");
  check(close(palpa::parse_quantity("2 mm", palpa::Dimension::Length, where), 2.0e-3, 1e-12),
        "\"2 mm\" is 0.002 m");
  bool rejected = false;
  try {
    palpa::parse_quantity("2 mm", palpa::Dimension::Pressure, where);
  } catch (const palpa::Error& e) {
    rejected = e.kind() == palpa::ErrorKind::Input;
  }
  check(rejected, "a length where a pressure is expected throws palpa::Error (Input)");
}

void check_material() {
  const double young = 10.0e3;  // Pa
  const double poisson = 0.45;
  const palpa::material::NeoHookean m(young, poisson);
  const palpa::material::ElasticConstants c = palpa::material::small_strain_constants(m);
  check(close(c.young(), young, 1e-6), "neo-Hookean: small-strain Young's modulus is E");
  check(close(c.poisson(), poisson, 1e-6), "neo-Hookean: small-strain Poisson's ratio is nu");
  // Uniaxial stretch by 0.1 %: P11 = E (s - 1) to first order in the strain.
  const double s = 1.001;
  const palpa::material::CurvePoint p =
      palpa::material::homogeneous_point(m, palpa::material::LoadCase::Uniaxial, s);
  check(close(p.nominal, young * (s - 1.0), 5e-3), "neo-Hookean: uniaxial P11 = E (s - 1) at small strain");
  check(p.lateral < 1.0, "neo-Hookean: uniaxial tension contracts laterally");
}

void check_cholmod_solve() {
  // The 1D Laplacian with Dirichlet ends (lower triangle only), A x = b.
  const int n = 5;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 2.0);
    if (i + 1 < n) entries.emplace_back(i + 1, i, -1.0);
  }
  Eigen::SparseMatrix<double> lower(n, n);
  lower.setFromTriplets(entries.begin(), entries.end());
  Eigen::MatrixXd full = Eigen::MatrixXd(lower);
  full = full.selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);

  palpa::SparseCholesky chol;
  const palpa::FactorStatus status = chol.factorize(lower);
  check(status == palpa::FactorStatus::Ok, "CHOLMOD factorizes the SPD matrix");
  if (status != palpa::FactorStatus::Ok) return;
  const Eigen::MatrixXd x = chol.solve(b);
  check((full * x - b).norm() <= 1e-12 * b.norm(), "CHOLMOD solves A x = b");
}

}  // namespace

int main() {
  try {
    check_version();
    check_units();
    check_material();
    check_cholmod_solve();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAILED: unexpected exception: %s\n", e.what());
    return 1;
  }
  if (failures > 0) return 1;
  std::printf("palpa %s: all checks passed\n", palpa::kVersion);
  return 0;
}
