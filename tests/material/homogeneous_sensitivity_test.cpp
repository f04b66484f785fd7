// SPDX-License-Identifier: AGPL-3.0-or-later
// Parameter derivatives of homogeneous curve points (homogeneous.hpp):
//  - d(nominal, cauchy, lateral)/dθ against central finite differences in every
//    parameter, for every model and load case, in compression and tension;
//  - exact identities: (E, ν) models scale linearly in E at fixed ν, and every
//    model's energy is homogeneous of degree 1 in its moduli;
//  - simple shear at γ = 0, and the curve version against the point version.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "common/finite_difference.hpp"
#include "model_fixtures.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {
namespace {

using test::param_scale;

using palpa::test::derivatives_match;
using palpa::test::fd_jacobian;
using palpa::test::ZeroPolicy;
using test::ModelCase;

// Agreement demanded of analytic vs finite-difference derivatives, relative to
// the larger of the two (or to the reference magnitude where both are small).
constexpr double kFdTolerance = 1e-6;
// Relative step of the finite differences, per unit of each parameter's size.
constexpr double kFdStep = 1e-4;
// Reference magnitude of d(lateral)/d(relative change of θk): lateral
// derivatives far below it are compared against it, not against themselves.
constexpr double kLateralReference = 1e-2;

std::string case_name(LoadCase c) {
  switch (c) {
    case LoadCase::Uniaxial: return "Uniaxial";
    case LoadCase::Equibiaxial: return "Equibiaxial";
    case LoadCase::SimpleShear: return "SimpleShear";
  }
  return "?";
}

// Largest equibiaxial stretch of the StVK fixture (ν = 0.3) with a lateral
// equilibrium: E33 = −2ν/(1 − ν) E11 reaches −½ (t = 0) at s ≈ 1.47.
constexpr double kStvkMaxEquibiaxial = 1.4;

// Stretches in compression and tension; shears small and large, both signs.
// A model that collapses (not inversion-safe: StVK) is probed in equibiaxial
// tension only up to where a traction-free lateral stretch exists.
std::vector<double> probe_loads(LoadCase c, bool inversion_safe = true) {
  if (c == LoadCase::SimpleShear) return {0.05, 0.5, -0.3};
  if (c == LoadCase::Equibiaxial && !inversion_safe) return {0.6, 0.9, 1.3, kStvkMaxEquibiaxial};
  return {0.6, 0.9, 1.3, 1.8};
}

// Rows (nominal, cauchy, lateral) × parameters, by central differences in θ;
// each perturbed solve starts from the unperturbed lateral stretch.
Eigen::MatrixXd fd_point_dparam(const Material& m, LoadCase c, double load, double lateral,
                                const Eigen::VectorXd& scale) {
  const Eigen::VectorXd theta0 = m.params();
  auto work = m.clone();
  const auto g = [&](const Eigen::VectorXd& x) {
    work->set_params(theta0 + scale.cwiseProduct(x));
    const CurvePoint p = homogeneous_point(*work, c, load, lateral);
    return Eigen::Vector3d(p.nominal, p.cauchy, p.lateral).eval();
  };
  const Eigen::MatrixXd jac = fd_jacobian(
      [&](const Eigen::VectorXd& x) { return Eigen::VectorXd(g(x)); },
      Eigen::VectorXd::Zero(theta0.size()), kFdStep);
  return jac * scale.cwiseInverse().asDiagonal();
}

// Largest |a − n| / max(|a|, |n|, reference) over the entries.
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& n, double reference) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double scale = std::max({std::abs(a(i)), std::abs(n(i)), reference});
    worst = std::max(worst, std::abs(a(i) - n(i)) / scale);
  }
  return worst;
}

class HomogeneousSensitivity
    : public ::testing::TestWithParam<std::tuple<ModelCase, LoadCase>> {
 protected:
  void SetUp() override { m_ = std::get<0>(GetParam()).make(); }
  LoadCase load_case() const { return std::get<1>(GetParam()); }
  double modulus() const { return std::get<0>(GetParam()).expected.mu; }
  std::unique_ptr<Material> m_;
};

TEST_P(HomogeneousSensitivity, MatchesFiniteDifferencesInEveryParameter) {
  const LoadCase c = load_case();
  const Eigen::VectorXd ps = param_scale(*m_, modulus());
  double worst = 0.0;
  for (double load : probe_loads(c, std::get<0>(GetParam()).inversion_safe)) {
    const CurvePointSensitivity got = homogeneous_point_sensitivity(*m_, c, load);
    ASSERT_EQ(got.dnominal_dparams.size(), m_->num_params());
    ASSERT_EQ(got.dcauchy_dparams.size(), m_->num_params());
    ASSERT_EQ(got.dlateral_dparams.size(), m_->num_params());
    const Eigen::MatrixXd numeric = fd_point_dparam(*m_, c, load, got.point.lateral, ps);
    // Per relative change of each parameter.
    const Eigen::RowVectorXd nominal = got.dnominal_dparams.cwiseProduct(ps).transpose();
    const Eigen::RowVectorXd cauchy = got.dcauchy_dparams.cwiseProduct(ps).transpose();
    const Eigen::RowVectorXd lateral = got.dlateral_dparams.cwiseProduct(ps).transpose();
    const Eigen::RowVectorXd fd_nominal = numeric.row(0).cwiseProduct(ps.transpose());
    const Eigen::RowVectorXd fd_cauchy = numeric.row(1).cwiseProduct(ps.transpose());
    const Eigen::RowVectorXd fd_lateral = numeric.row(2).cwiseProduct(ps.transpose());
    // The stress depends on the parameters: the test can fail.
    EXPECT_TRUE(derivatives_match(nominal, fd_nominal, kFdTolerance)) << "load " << load;
    for (Eigen::Index k = 0; k < m_->num_params(); ++k) {
      const std::string where =
          "load " + std::to_string(load) + ", parameter " + m_->param_info(k).name;
      EXPECT_TRUE(derivatives_match(nominal.segment(k, 1), fd_nominal.segment(k, 1),
                                    kFdTolerance, ZeroPolicy::MayBeZero, modulus()))
          << where << " (nominal)";
      EXPECT_TRUE(derivatives_match(cauchy.segment(k, 1), fd_cauchy.segment(k, 1), kFdTolerance,
                                    ZeroPolicy::MayBeZero, modulus()))
          << where << " (cauchy)";
      EXPECT_TRUE(derivatives_match(lateral.segment(k, 1), fd_lateral.segment(k, 1),
                                    kFdTolerance, ZeroPolicy::MayBeZero, kLateralReference))
          << where << " (lateral)";
    }
    if (c == LoadCase::SimpleShear) {
      EXPECT_EQ(got.dlateral_dparams.cwiseAbs().maxCoeff(), 0.0);
    }
    worst = std::max({worst, relative_error(nominal, fd_nominal, modulus()),
                      relative_error(cauchy, fd_cauchy, modulus()),
                      relative_error(lateral, fd_lateral, kLateralReference)});
  }
  std::ostringstream text;
  text << std::scientific << std::setprecision(2) << worst;
  RecordProperty("worst_relative_error", text.str());
}

// Weight of θk in the degree-1 homogeneity of Ψ: scaling every modulus by a
// (and every compliance by 1/a) scales Ψ, hence P and σ, by a at the same
// stretches, and leaves the lateral stretch unchanged. So
//   Σk wk θk dP/dθk = P,  Σk wk θk dt/dθk = 0,  wk = 1 (Pa), −1 (1/Pa), 0 (ratio).
double homogeneity_weight(const ParamInfo& info) {
  if (info.dimension == Dimension::Pressure) return 1.0;
  if (info.dimension == Dimension::Compliance) return -1.0;
  return 0.0;
}

TEST_P(HomogeneousSensitivity, ModuliScaleTheStressExactly) {
  const LoadCase c = load_case();
  Eigen::VectorXd w(m_->num_params());
  for (Eigen::Index k = 0; k < w.size(); ++k) w[k] = homogeneity_weight(m_->param_info(k));
  ASSERT_GT(w.cwiseAbs().sum(), 0.0);
  const Eigen::VectorXd theta = m_->params();
  for (double load : probe_loads(c, std::get<0>(GetParam()).inversion_safe)) {
    const CurvePointSensitivity got = homogeneous_point_sensitivity(*m_, c, load);
    const double tol = 1e-9 * std::max(std::abs(got.point.nominal), modulus());
    EXPECT_NEAR(w.cwiseProduct(theta).dot(got.dnominal_dparams), got.point.nominal, tol) << load;
    EXPECT_NEAR(w.cwiseProduct(theta).dot(got.dcauchy_dparams), got.point.cauchy, tol) << load;
    EXPECT_NEAR(w.cwiseProduct(theta).dot(got.dlateral_dparams), 0.0, 1e-9) << load;
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllModels, HomogeneousSensitivity,
    ::testing::Combine(::testing::ValuesIn(test::all_model_cases()),
                       ::testing::Values(LoadCase::Uniaxial, LoadCase::Equibiaxial,
                                         LoadCase::SimpleShear)),
    [](const auto& test_info) {
      return std::get<0>(test_info.param).name + "_" + case_name(std::get<1>(test_info.param));
    });

TEST(HomogeneousSensitivityClosedForm, NeoHookeanStressIsLinearInYoungsModulus) {
  // μ and λ are both proportional to E at fixed ν, so the lateral stretch does
  // not depend on E and P, σ are proportional to it: dP/dE = P/E, dt/dE = 0.
  const double young = 12e3;
  for (const LoadCase c : {LoadCase::Uniaxial, LoadCase::Equibiaxial, LoadCase::SimpleShear}) {
    for (const double nu : {0.3, 0.45, 0.49}) {
      const NeoHookean m(young, nu);
      for (double load : probe_loads(c)) {
        const CurvePointSensitivity got = homogeneous_point_sensitivity(m, c, load);
        const double tol = 1e-12 * std::abs(got.point.nominal);
        ASSERT_GT(std::abs(got.point.nominal), 0.0);
        EXPECT_NEAR(got.dnominal_dparams[0], got.point.nominal / young, tol / young)
            << case_name(c) << " nu " << nu << " load " << load;
        EXPECT_NEAR(got.dcauchy_dparams[0], got.point.cauchy / young,
                    1e-12 * std::abs(got.point.cauchy) / young)
            << case_name(c) << " nu " << nu << " load " << load;
        EXPECT_NEAR(got.dlateral_dparams[0] * young, 0.0, 1e-10)
            << case_name(c) << " nu " << nu << " load " << load;
        if (c != LoadCase::SimpleShear) {
          // ν moves the lateral stretch (more lateral contraction as ν grows).
          EXPECT_NE(got.dlateral_dparams[1], 0.0);
        }
      }
    }
  }
}

TEST(HomogeneousSensitivityClosedForm, SimpleShearDerivativesVanishAtRestAndAreOddInShear) {
  // P12(γ) is odd in γ for an isotropic material, for every θ.
  for (const ModelCase& mc : test::all_model_cases()) {
    const auto m = mc.make();
    const CurvePointSensitivity rest = homogeneous_point_sensitivity(*m, LoadCase::SimpleShear, 0.0);
    ASSERT_TRUE(rest.dnominal_dparams.allFinite()) << mc.name;
    EXPECT_EQ(rest.dnominal_dparams.cwiseAbs().maxCoeff(), 0.0) << mc.name;
    EXPECT_EQ(rest.dcauchy_dparams.cwiseAbs().maxCoeff(), 0.0) << mc.name;
    for (double g : {1e-6, 0.3}) {
      const auto plus = homogeneous_point_sensitivity(*m, LoadCase::SimpleShear, g);
      const auto minus = homogeneous_point_sensitivity(*m, LoadCase::SimpleShear, -g);
      const Eigen::VectorXd ps = param_scale(*m, mc.expected.mu);
      EXPECT_GT(plus.dnominal_dparams.cwiseProduct(ps).norm(), 0.0) << mc.name << " γ " << g;
      EXPECT_TRUE(derivatives_match(plus.dnominal_dparams.cwiseProduct(ps),
                                    -minus.dnominal_dparams.cwiseProduct(ps), 1e-9,
                                    ZeroPolicy::MustBeNonZero))
          << mc.name << " γ " << g;
    }
  }
}

TEST(HomogeneousCurveSensitivity, MatchesPointsInAnyLoadOrder) {
  for (const ModelCase& mc : test::all_model_cases()) {
    const auto m = mc.make();
    for (const LoadCase c : {LoadCase::Uniaxial, LoadCase::Equibiaxial, LoadCase::SimpleShear}) {
      std::vector<double> loads =
          c == LoadCase::SimpleShear
              ? std::vector<double>{0.5, -0.2, 0.0, 0.05, 0.5, -0.45}
              : std::vector<double>{1.8, 0.6, 1.0, 1.3, 0.9, 1.3, 0.75, 1.02};
      if (c == LoadCase::Equibiaxial && !mc.inversion_safe) loads.front() = kStvkMaxEquibiaxial;
      const CurveSensitivity curve = homogeneous_curve_sensitivity(*m, c, loads);
      ASSERT_EQ(curve.points.size(), loads.size());
      ASSERT_EQ(curve.dnominal_dparams.rows(), static_cast<Eigen::Index>(loads.size()));
      ASSERT_EQ(curve.dnominal_dparams.cols(), m->num_params());
      for (std::size_t i = 0; i < loads.size(); ++i) {
        const auto row = static_cast<Eigen::Index>(i);
        const CurvePointSensitivity p = homogeneous_point_sensitivity(*m, c, loads[i]);
        const std::string where = mc.name + " " + case_name(c) + " load " + std::to_string(loads[i]);
        EXPECT_EQ(curve.points[i].load, loads[i]) << where;
        EXPECT_NEAR(curve.points[i].nominal, p.point.nominal, 1e-10 * mc.expected.mu) << where;
        EXPECT_NEAR(curve.points[i].lateral, p.point.lateral, 1e-12) << where;
        const Eigen::VectorXd ps = param_scale(*m, mc.expected.mu);
        const auto close = [&](const Eigen::MatrixXd& rows, const Eigen::VectorXd& point,
                               double reference) {
          return derivatives_match(rows.row(row).transpose().cwiseProduct(ps),
                                   point.cwiseProduct(ps), 1e-9, ZeroPolicy::MayBeZero, reference);
        };
        EXPECT_TRUE(close(curve.dnominal_dparams, p.dnominal_dparams, mc.expected.mu)) << where;
        EXPECT_TRUE(close(curve.dcauchy_dparams, p.dcauchy_dparams, mc.expected.mu)) << where;
        EXPECT_TRUE(close(curve.dlateral_dparams, p.dlateral_dparams, kLateralReference)) << where;
      }
    }
  }
}

TEST(HomogeneousCurveSensitivity, PointsMatchTheEvenlySpacedCurve) {
  const NeoHookean m(12e3, 0.45);
  for (const LoadCase c : {LoadCase::Uniaxial, LoadCase::Equibiaxial}) {
    const std::vector<CurvePoint> ref = homogeneous_curve(m, c, 0.6, 1.8, 25);
    std::vector<double> loads;
    for (const CurvePoint& p : ref) loads.push_back(p.load);
    const CurveSensitivity got = homogeneous_curve_sensitivity(m, c, loads);
    for (std::size_t i = 0; i < ref.size(); ++i) {
      EXPECT_NEAR(got.points[i].nominal, ref[i].nominal, 1e-10 * 12e3) << ref[i].load;
      EXPECT_NEAR(got.points[i].cauchy, ref[i].cauchy, 1e-10 * 12e3) << ref[i].load;
      EXPECT_NEAR(got.points[i].lateral, ref[i].lateral, 1e-12) << ref[i].load;
    }
  }
}

TEST(HomogeneousCurveSensitivity, EmptyAndInvalidLoads) {
  const NeoHookean m(12e3, 0.45);
  const CurveSensitivity empty = homogeneous_curve_sensitivity(m, LoadCase::Uniaxial, {});
  EXPECT_TRUE(empty.points.empty());
  EXPECT_EQ(empty.dnominal_dparams.rows(), 0);
  EXPECT_EQ(empty.dnominal_dparams.cols(), 2);
  const auto kind_of = [&](LoadCase c, std::vector<double> loads) {
    try {
      homogeneous_curve_sensitivity(m, c, loads);
    } catch (const Error& e) {
      return e.kind();
    }
    return ErrorKind::Internal;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(kind_of(LoadCase::Uniaxial, {1.1, nan}), ErrorKind::Input);
  EXPECT_EQ(kind_of(LoadCase::SimpleShear, {0.1, std::numeric_limits<double>::infinity()}),
            ErrorKind::Input);
  EXPECT_EQ(kind_of(LoadCase::Uniaxial, {1.1, -0.5}), ErrorKind::Input);
  EXPECT_THROW(homogeneous_point_sensitivity(m, LoadCase::Equibiaxial, 0.0), Error);
}

}  // namespace
}  // namespace palpa::material
