// SPDX-License-Identifier: AGPL-3.0-or-later
// A soft block hanging from a rigid core (its top face) falls onto a flat
// support: the contact force carries the weight, the pressure under the block
// is a uniform ρgH on both sides and both pressure maps carry the weight, the
// penetration lands at the target, locked core DOFs stay put, a
// torque on the core is balanced by the contact moment; bad setups refused.
#include <gtest/gtest.h>

#include <memory>

#include "common/test_support.hpp"
#include "palpa/material/models.hpp"
#include "palpa/rest/measurements.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"
#include "rest/block_constants.hpp"

namespace palpa::rest {
namespace {

using namespace test;

struct Block {
  RestBody body;
  std::vector<int> bottom;
};

Block block(int n = 8, double nu = 0.0) {
  Block b;
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-kW / 2, -kW / 2, 0.0), Eigen::Vector3d(kW / 2, kW / 2, kH),
                                        Eigen::Vector3i(n, n, n / 2));
  b.body.mesh = box.mesh;
  b.body.attached = box.vertex_sets.at("top");
  b.body.materials = {{std::make_shared<material::NeoHookean>(20e3, nu), kRho}};
  b.bottom = box.vertex_sets.at("bottom");
  return b;
}

// A 200 × 200 × 50 mm slab whose top face lies `gap` below z = 0.
SurfaceMesh slab(double gap, int divisions = 40) {
  SurfaceMesh s = sim3d::make_box_surface(Eigen::Vector3d(0.2, 0.2, 0.05), divisions);
  s.V.col(2).array() -= 0.05 + gap;
  return s;
}

RestOptions vertical_only() {
  RestOptions o;
  o.core.locked = {true, true, false, true, true, true};
  return o;
}

TEST(Rest, BlockOnASlabCarriesItsWeightWithPressureRhoGH) {
  Block b = block();
  RestSimulation sim(b.body, slab(5e-4), vertical_only());
  const RestResult r = sim.solve();
  const double weight = kRho * kW * kW * kH * kG;
  EXPECT_NEAR(r.contact_force.z(), weight, 0.005 * weight);
  EXPECT_LT(r.balance_error, 0.005);
  EXPECT_NEAR(r.contact_force.x(), 0.0, 1e-6 * weight);
  // A uniform pressure ρgH under the block (ν = 0: each column carries its
  // own weight), on every bottom vertex but the rim's (whose skin share
  // reaches up the block's sides) within 1%.
  const double rho_g_h = kRho * kG * kH;
  const TetMesh& mesh = sim.model().mesh();
  int inside = 0;
  for (int v : b.bottom) {
    if (std::max(std::abs(mesh.V(v, 0)), std::abs(mesh.V(v, 1))) < 0.5 * kW - 1e-9) {
      EXPECT_NEAR(r.body_pressure[v], rho_g_h, 0.01 * rho_g_h) << v;
      ++inside;
    }
  }
  EXPECT_EQ(inside, 7 * 7);
  // The support sees the same pressure under the block, a footprint in from
  // its rim (its own vertices against the deformed body), and none farther
  // than a footprint out.
  const double footprint = pressure_recovery(sim).support.radius();
  EXPECT_GT(footprint, 0.0);
  EXPECT_LT(footprint, kW / 4);
  int under = 0;
  for (Eigen::Index v = 0; v < sim.support().vertices().rows(); ++v) {
    const Eigen::Vector3d q = sim.support().world_vertex(static_cast<int>(v));
    const double from_centre = std::max(std::abs(q.x()), std::abs(q.y()));
    if (from_centre < 0.5 * kW - footprint && q.z() > -1e-3) {
      EXPECT_NEAR(r.support_pressure[v], rho_g_h, 0.01 * rho_g_h) << v;
      ++under;
    }
    if (from_centre > 0.5 * kW + footprint) EXPECT_EQ(r.support_pressure[v], 0.0);
  }
  EXPECT_GE(under, 9);
  // Both maps carry the load: Σ p·A on each side is the weight, and the
  // nodal forces on the two sides are equal and opposite.
  EXPECT_NEAR(r.body_map_force, weight, 0.01 * weight);
  EXPECT_NEAR(r.support_map_force, weight, 0.01 * weight);
  const ContactPressures cp = contact_pressures(sim);
  EXPECT_LT((cp.body_force.rowwise().sum() + cp.support_force.rowwise().sum()).norm(), 1e-6 * weight);
  EXPECT_NEAR(cp.body_force.rowwise().sum().z(), weight, 0.005 * weight);
  // What a mat would read on each side: the weight over the block's
  // footprint, centred under it; the mean, the peak pressure index and the
  // peak ρgH.
  for (const report::PressureMetrics& m : {r.body_metrics, r.support_metrics}) {
    EXPECT_NEAR(m.force, weight, 0.01 * weight);
    EXPECT_NEAR(m.contact_area, kW * kW, 0.01 * kW * kW);
    EXPECT_LT(m.centre.head<2>().norm(), 0.01 * kW);
    EXPECT_NEAR(m.mean, rho_g_h, 0.01 * rho_g_h);
    EXPECT_NEAR(m.peak_pressure_index, rho_g_h, 0.01 * rho_g_h);
    EXPECT_NEAR(m.peak, rho_g_h, 0.01 * rho_g_h);
    EXPECT_LE(m.peak_pressure_index, m.peak);
    EXPECT_LE(m.p95, m.peak);
    EXPECT_GT(m.dispersion_index, 0.0);
    EXPECT_LE(m.dispersion_index, 1.0);
  }
  // The automatic stiffness put the deepest penetration at the 0.3 mm target.
  EXPECT_GT(r.max_penetration, 0.85 * 3e-4);
  EXPECT_LT(r.max_penetration, 1.15 * 3e-4);
  // Locked DOFs stayed locked; the free one fell through the gap.
  EXPECT_EQ(r.core_translation.x(), 0.0);
  EXPECT_EQ(r.core_translation.y(), 0.0);
  EXPECT_TRUE(r.core_rotation.isIdentity(0.0));
  EXPECT_LT(r.core_translation.z(), -5e-4);
  EXPECT_GT(r.min_det_f, 0.0);
}

TEST(Rest, TorqueOnTheCoreIsBalancedByTheContactMoment) {
  // Vertical translation and pitch free (the foot of §7.5.2), a core mass and
  // a pitch torque.
  Block b = block();
  RestOptions o;
  o.core.locked = {true, true, false, true, false, true};
  o.core.mass = 0.1;
  o.core.torque = Eigen::Vector3d(0.0, 2e-3, 0.0);
  o.core.force = Eigen::Vector3d(0.0, 0.0, -0.5);
  RestSimulation sim(b.body, slab(5e-4), o);
  const RestResult r = sim.solve();
  const double load = (kRho * kW * kW * kH + 0.1) * kG + 0.5;
  EXPECT_NEAR(r.contact_force.z(), load, 0.005 * load);
  // Moment balance about the core's centre (pitch): contact moment = −torque.
  EXPECT_NEAR(r.contact_torque.y(), -2e-3, 0.02 * 2e-3);
  EXPECT_GT(std::abs(r.core_rotation(0, 2)), 1e-5);  // it pitched
  EXPECT_NEAR(r.core_rotation(1, 1), 1.0, 1e-15);    // about y only
}

TEST(Rest, RefusesBadSetups) {
  Block b = block(4);
  // A body starting inside the support.
  EXPECT_TRUE(palpa::test::throws_error([&] { RestSimulation s(b.body, slab(-1e-3, 8), vertical_only()); },
                                        ErrorKind::Input, {"starts inside support", "place it slightly above"}));
  // A support that is not closed.
  SurfaceMesh open = slab(1e-3, 1);
  open.F.conservativeResize(open.F.rows() - 2, 3);
  EXPECT_TRUE(palpa::test::throws_error([&] { RestSimulation s(b.body, open, vertical_only()); }, ErrorKind::Input,
                                        {"support", "not closed"}));
  // A core with no attached vertex.
  RestBody loose = b.body;
  loose.attached.clear();
  EXPECT_TRUE(palpa::test::throws_error([&] { RestSimulation s(loose, slab(1e-3, 8), vertical_only()); },
                                        ErrorKind::Input, {"no attached vertices"}));
}

// The lift that frees a body from a support it starts inside: the least
// distance along `up` (to 1e-3 of it) plus the margin; 0 for a body above.
TEST(Rest, LiftsABodyClearOfASupportItStartsInside) {
  const Block b = block(4);
  const Eigen::Vector3d up(0.0, 0.0, 2.0);  // any length
  EXPECT_EQ(lift_clear_of(b.body, slab(1e-3, 8), up, 1e-3), 0.0);
  const double lift = lift_clear_of(b.body, slab(-3e-3, 8), up, 0.0);
  EXPECT_GE(lift, 3e-3 - 1e-12);
  EXPECT_LE(lift, 3e-3 * (1.0 + 1e-3));
  EXPECT_NEAR(lift_clear_of(b.body, slab(-3e-3, 8), up, 1e-3), lift + 1e-3, 1e-15);
  // Lifted by it, the body is accepted above that support.
  RestBody lifted = b.body;
  lifted.mesh.V.col(2).array() += lift + 1e-6;
  EXPECT_NO_THROW(RestSimulation(lifted, slab(-3e-3, 8), vertical_only()));
}

}  // namespace
}  // namespace palpa::rest
