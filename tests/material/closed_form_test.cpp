// SPDX-License-Identifier: AGPL-3.0-or-later
// Homogeneous tests against closed-form stresses.
#include <gtest/gtest.h>

#include <cmath>

#include "palpa/material/checks.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/kinematics.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::material {
namespace {

constexpr double kE = 12e3;

TEST(ClosedForm, CompressibleNeoHookeanUniaxialSatisfiesItsEquations) {
  // For λ = (s, t, t): P11 = μ (s − 1/s) + λ ln J / s and the lateral equation
  // μ (t − 1/t) + λ ln J / t = 0 (Bonet & Wood form).
  const NeoHookean m(kE, 0.3);
  const ElasticConstants l = lame_from_young(kE, 0.3);
  for (double s : {0.6, 0.85, 1.0, 1.3, 1.6}) {
    const CurvePoint p = homogeneous_point(m, LoadCase::Uniaxial, s);
    const double t = p.lateral;
    const double lnj = std::log(s * t * t);
    EXPECT_NEAR(l.mu * (t - 1.0 / t) + l.lambda * lnj / t, 0.0, 1e-9 * kE) << s;
    EXPECT_NEAR(p.nominal, l.mu * (s - 1.0 / s) + l.lambda * lnj / s, 1e-9 * kE) << s;
    EXPECT_NEAR(p.cauchy, p.nominal * s / (s * t * t), 1e-9 * kE) << s;
  }
}

TEST(ClosedForm, NearlyIncompressibleNeoHookeanMatchesIncompressibleFormulas) {
  // ν → 0.5: uniaxial P = μ (s − s^-2), equibiaxial P = μ (s − s^-5). The
  // compressible model approaches these to O(μ/λ) = O(1e-6) times a factor
  // that grows with the stretch.
  const double nu = 0.499999;
  const NeoHookean m(kE, nu);
  const double mu = lame_from_young(kE, nu).mu;
  for (double s : {0.7, 0.9, 1.2, 1.5}) {
    const double uni = homogeneous_point(m, LoadCase::Uniaxial, s).nominal;
    EXPECT_NEAR(uni, mu * (s - 1.0 / (s * s)), 2e-4 * mu) << s;
    const double bi = homogeneous_point(m, LoadCase::Equibiaxial, s).nominal;
    EXPECT_NEAR(bi, mu * (s - std::pow(s, -5.0)), 2e-4 * mu) << s;
  }
}

TEST(ClosedForm, NearlyIncompressibleMooneyRivlinMatchesIncompressibleFormulas) {
  // Uniaxial P = 2 (s − s^-2)(C10 + C01/s); equibiaxial P = 2 (s − s^-5)(C10 + C01 s²).
  const double c10 = 1500.0;
  const double c01 = 400.0;
  const double d1 = 2.0 / (1e6 * 2.0 * (c10 + c01));  // K = 1e6 μ
  const IsochoricInvariant m = IsochoricInvariant::mooney_rivlin(c10, c01, d1);
  const double mu = 2.0 * (c10 + c01);
  for (double s : {0.7, 0.9, 1.2, 1.5}) {
    const double uni = homogeneous_point(m, LoadCase::Uniaxial, s).nominal;
    EXPECT_NEAR(uni, 2.0 * (s - 1.0 / (s * s)) * (c10 + c01 / s), 1e-4 * mu) << s;
    const double bi = homogeneous_point(m, LoadCase::Equibiaxial, s).nominal;
    EXPECT_NEAR(bi, 2.0 * (s - std::pow(s, -5.0)) * (c10 + c01 * s * s), 1e-4 * mu) << s;
  }
}

TEST(ClosedForm, IsochoricNeoHookeanSimpleShearIsLinear) {
  // Simple shear keeps J = 1, so σ12 = 2 C10 γ exactly, with the Poynting
  // normal stresses σ11 − σ22 = 2 C10 γ².
  const double c10 = 2000.0;
  const IsochoricInvariant m = IsochoricInvariant::neo_hookean(c10, 1e-6);
  for (double g : {-0.8, -0.1, 0.3, 1.0}) {
    const CurvePoint p = homogeneous_point(m, LoadCase::SimpleShear, g);
    EXPECT_NEAR(p.cauchy, 2.0 * c10 * g, 1e-9 * c10) << g;
    EXPECT_NEAR(p.cauchy_11 - p.cauchy_22, 2.0 * c10 * g * g, 1e-9 * c10) << g;
  }
}

TEST(ClosedForm, SmallStrainUniaxialGivesYoungsModulusForEveryModel) {
  // dP/ds at s = 1 equals E, and the lateral contraction is −ν s.
  const double nu = 0.3;
  const ElasticConstants l = lame_from_young(kE, nu);
  const NeoHookean nh(kE, nu);
  const StVenantKirchhoff stvk(kE, nu);
  const Corotational corot(kE, nu);
  const IsochoricInvariant iso = IsochoricInvariant::neo_hookean(l.mu / 2.0, 2.0 / l.bulk());
  const Ogden og({l.mu}, {2.0}, nu);
  for (const Material* m : std::initializer_list<const Material*>{&nh, &stvk, &corot, &iso, &og}) {
    const double h = 1e-6;
    const CurvePoint a = homogeneous_point(*m, LoadCase::Uniaxial, 1.0 + h);
    const CurvePoint b = homogeneous_point(*m, LoadCase::Uniaxial, 1.0 - h);
    EXPECT_NEAR((a.nominal - b.nominal) / (2.0 * h), kE, 1e-5 * kE) << m->model();
    EXPECT_NEAR((a.lateral - b.lateral) / (2.0 * h), -nu, 1e-5) << m->model();
  }
}

TEST(ClosedForm, OneTermOgdenWithAlphaTwoIsNeoHookean) {
  const double nu = 0.45;
  const NeoHookean nh(kE, nu);
  const Ogden og({lame_from_young(kE, nu).mu}, {2.0}, nu);
  for (const Vec3& l : {Vec3(1.2, 0.9, 0.8), Vec3(0.5, 1.6, 1.1)}) {
    EXPECT_NEAR(og.psi(l), nh.psi(l), 1e-10 * kE);
    EXPECT_LE((og.dpsi_dlambda(l) - nh.dpsi_dlambda(l)).cwiseAbs().maxCoeff(), 1e-10 * kE);
  }
}

TEST(ClosedForm, VolumeTermChangesFiniteStrainButNotSmallStrain) {
  // Same E, ν: identical at small strain, different by more than a percent at
  // 30% compression (the finite-strain volumetric response differs).
  const NeoHookean plain(kE, 0.45);
  const NeoHookean vol = NeoHookean::with_volume_term(kE, 0.45, 0.5);
  const double small_a = homogeneous_point(plain, LoadCase::Uniaxial, 0.999).nominal;
  const double small_b = homogeneous_point(vol, LoadCase::Uniaxial, 0.999).nominal;
  EXPECT_NEAR(small_a, small_b, 2e-3 * std::abs(small_a));
  const double big_a = homogeneous_point(plain, LoadCase::Uniaxial, 0.7).nominal;
  const double big_b = homogeneous_point(vol, LoadCase::Uniaxial, 0.7).nominal;
  EXPECT_GT(std::abs(big_a - big_b), 1e-3 * std::abs(big_a));
}

TEST(SplineFromModel, ReproducesNeoHookeanCurvesWithErrorFallingWithKnots) {
  const NeoHookean nh(kE, 0.45);
  const auto curve_error = [&](int knots) {
    SplineLayout layout;
    layout.f = {0.5, 2.0, knots};
    layout.g = {0.4, 2.5, knots};
    layout.h = {0.6, 1.6, knots};
    const SplineMaterial s = SplineMaterial::from_model(nh, layout);
    double worst = 0.0;
    for (LoadCase c : {LoadCase::Uniaxial, LoadCase::Equibiaxial}) {
      const auto ref = homogeneous_curve(nh, c, 0.7, 1.5, 17);
      const auto got = homogeneous_curve(s, c, 0.7, 1.5, 17);
      double peak = 0.0;
      for (const auto& p : ref) peak = std::max(peak, std::abs(p.nominal));
      for (std::size_t i = 0; i < ref.size(); ++i) {
        worst = std::max(worst, std::abs(got[i].nominal - ref[i].nominal) / peak);
      }
    }
    return worst;
  };
  const double e6 = curve_error(6);
  const double e12 = curve_error(12);
  const double e24 = curve_error(24);
  RecordProperty("error_6_knots", std::to_string(e6));
  RecordProperty("error_24_knots", std::to_string(e24));
  EXPECT_LT(e12, 0.6 * e6);
  EXPECT_LT(e24, 0.6 * e12);
  EXPECT_LT(e24, 0.01);  // within 1% of the peak stress
}

TEST(SplineFromModel, MooneyRivlinProjectionTracksItsStresses) {
  const double c10 = 1500.0;
  const double c01 = 400.0;
  const IsochoricInvariant mr = IsochoricInvariant::mooney_rivlin(c10, c01, 2.0 / (20.0 * 3800.0));
  SplineLayout layout;
  layout.f = {0.5, 2.0, 14};
  layout.g = {0.4, 2.5, 14};
  layout.h = {0.6, 1.6, 14};
  const SplineMaterial s = SplineMaterial::from_model(mr, layout);
  const auto ref = homogeneous_curve(mr, LoadCase::Uniaxial, 0.7, 1.5, 9);
  const auto got = homogeneous_curve(s, LoadCase::Uniaxial, 0.7, 1.5, 9);
  double peak = 0.0;
  for (const auto& p : ref) peak = std::max(peak, std::abs(p.nominal));
  for (std::size_t i = 0; i < ref.size(); ++i) {
    EXPECT_NEAR(got[i].nominal, ref[i].nominal, 0.03 * peak) << ref[i].load;
  }
}

TEST(SplineMaterial, RestStateStaysStressFreeForAnyControlValues) {
  SplineMaterial s = SplineMaterial::from_model(NeoHookean(kE, 0.4));
  Eigen::VectorXd theta = s.params();
  for (Eigen::Index k = 0; k < theta.size(); ++k) theta[k] += 300.0 * std::sin(1.7 * k + 0.3);
  s.set_params(theta);
  EXPECT_NE(s.rest_correction(), 0.0);
  EXPECT_LE(s.dpsi_dlambda(Vec3::Ones()).cwiseAbs().maxCoeff(), 1e-10 * kE);
  EXPECT_NEAR(s.psi(Vec3::Ones()), 0.0, 1e-10 * kE);
}

}  // namespace
}  // namespace palpa::material

namespace palpa::material {
namespace {

TEST(Checks, ClassicModelsPassAndABrokenSplineIsFlagged) {
  const MaterialCheck ok = check_material(NeoHookean(kE, 0.45));
  EXPECT_TRUE(ok.problems.empty()) << ok.problems.front();
  EXPECT_NEAR(ok.small_strain.young(), kE, 1e-8 * kE);
  EXPECT_NEAR(ok.small_strain.poisson(), 0.45, 1e-10);

  // A spline whose f softens strongly in tension: stable at rest, unstable in
  // uniaxial tension.
  SplineMaterial s = SplineMaterial::from_model(NeoHookean(kE, 0.45));
  Eigen::VectorXd theta = s.params();
  const auto& fk = s.spline(SplineMaterial::Part::F).knots();
  for (std::size_t k = 0; k < fk.size(); ++k) {
    if (fk[k] > 1.3) theta[static_cast<Eigen::Index>(k)] -= 40.0 * kE * (fk[k] - 1.3) * (fk[k] - 1.3);
  }
  s.set_params(theta);
  const MaterialCheck bad = check_material(s);
  ASSERT_FALSE(bad.problems.empty());
  EXPECT_NE(bad.problems.front().find("uniaxial"), std::string::npos) << bad.problems.front();
}

// The foam example's material (Yeoh, ν = 0.25) gives way in uniaxial
// compression near a stretch of 0.51 (its bulk term (J − 1)²/D1 stops growing
// as J → 0); a neo-Hookean with a logarithmic volumetric term never does.
TEST(Checks, TheCompressionLimitOfAMaterialThatGivesWay) {
  const IsochoricInvariant foam = IsochoricInvariant::yeoh(8e3, 2e3, 500.0, 7.5e-5);
  const double limit = uniaxial_compression_limit(foam);
  EXPECT_GE(limit, 0.5);
  EXPECT_LE(limit, 0.525);
  const auto below = homogeneous_point(foam, LoadCase::Uniaxial, limit - 0.01).nominal;
  const auto at = homogeneous_point(foam, LoadCase::Uniaxial, limit).nominal;
  EXPECT_GE(below, at);  // no more resistance below it
  EXPECT_EQ(uniaxial_compression_limit(NeoHookean(kE, 0.45)), 0.0);
  EXPECT_EQ(uniaxial_compression_limit(NeoHookean(kE, 0.25)), 0.0);
}

}  // namespace
}  // namespace palpa::material
