// SPDX-License-Identifier: AGPL-3.0-or-later
// Indentation of a soft block in 3D against what it must match: the
// axisymmetric simulator for a cylinder at the block's centre (thesis §6.3.3,
// Fig. 6.7), a square indenter's monotone force with bounded penetration and no
// inverted element, and local poking against the full mesh (§5.5).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <fmt/format.h>
#include <numbers>

#include "common/test_support.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/material/models.hpp"
#include "palpa/sim3d/run.hpp"
#include "scene_fixtures.hpp"

namespace palpa::sim3d {
namespace {

using palpa::test::ScratchDir;
using test::PunchScene;
using test::write_punch_scene;

struct Curve {
  std::vector<double> force;
  double seconds = 0.0;
  int min_contacts = 0;
  double max_penetration = 0.0;
  double min_det_f = 1.0;
};

Curve simulate(const Scene& s) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(s);
  Curve c;
  c.min_contacts = 1 << 30;
  for (int k = 1; k <= s.steps; ++k) {
    const StepRecord r = sim.solve_step(k);
    c.force.push_back(r.obstacles[0].indentation_force);
    c.min_contacts = std::min(c.min_contacts, r.obstacles[0].contacts);
    c.max_penetration = std::max(c.max_penetration, r.obstacles[0].max_penetration);
    c.min_det_f = std::min(c.min_det_f, r.min_det_f);
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

// A 4 mm flat punch 0.5 mm into a 10 mm layer, frictionless or stuck to the
// surface it presses, 3D against the axisymmetric solver (thesis §6.3.3,
// Fig. 6.7). The 3D body is a quarter of
// the axisymmetric layer itself (R = 22.57 mm, the area of a 40 × 40 mm block,
// free side wall): its cells are the layer's graded (r, z) grid at the same
// mesh level swept around the axis, with a ring of nodes on the punch's rim,
// and springs on surface samples; the two models then differ by their
// elements only, and the axisymmetric force at level 4 is the reference
// (levels 4 and 5 agree within 0.1%).
struct PunchRow {
  double reference = 0.0;
  std::vector<double> force;  // 3D, by level
};

// The layer under the punch [m]: the punch radius, the layer's thickness and
// outer radius, the depth, and the contact's largest penetration as a share
// of the depth.
struct Layer {
  double punch = 4e-3, thickness = 10e-3, radius = 22.57e-3, depth = 5e-4, penetration = 0.004;
};

// element: the body's element members ("\"element\": \"linear\"").
PunchRow flat_punch(double nu, axisym::PunchContact contact, int levels,
                    const std::string& element = R"("element": "linear")", int first_level = 0,
                    const Layer& layer = {}) {
  const bool stick = contact == axisym::PunchContact::Stick;
  const material::NeoHookean nh(10e3, nu);
  axisym::PokeSetup setup;
  setup.geometry = {layer.punch, layer.thickness, layer.radius};
  setup.contact = contact;
  setup.mesh_level = 4;
  axisym::PokeSimulator poke(nh, setup);
  axisym::PokeOptions po;
  po.max_depth = layer.depth;
  po.steps = 2;
  PunchRow row;
  row.reference = poke.run(po).samples.back().force;

  ScratchDir dir;
  for (int level = first_level; level < levels; ++level) {
    PunchScene p;
    p.body = fmt::format(R"("cylinder": {{"radius": "{} mm", "height": "{} mm", "rim": "{} mm", "level": {},
                                          "segments": 48, "sector": "90 deg"}}, {})",
                         layer.radius * 1e3, layer.thickness * 1e3, layer.punch * 1e3, level, element);
    p.fixed = R"([{"set": "bottom"}, {"set": "sector_start", "components": "y"},
                  {"set": "sector_end", "components": "x"}])";
    p.material = fmt::format(R"({{"model": "neo-hookean", "parameters": {{"E": "10 kPa", "nu": {}}}}})", nu);
    p.shape = fmt::format(R"({{"cylinder": {{"radius": "{} mm", "height": "10 mm", "segments": 48}}}})",
                          layer.punch * 1e3);
    p.depth = fmt::format("{} mm", layer.depth * 1e3);
    p.steps = 2;
    const double penetration = layer.penetration * layer.depth;
    p.contact = fmt::format(R"({{"max_penetration": "{} mm", "sampling": "surface", "subdivisions": 2,
                                 "friction": "{}"}})",
                            penetration * 1e3, stick ? "stick" : "frictionless");
    const Curve c = simulate(read_scene(write_punch_scene(dir, p, fmt::format("level{}.json", level))));
    row.force.push_back(4.0 * c.force.back());
    EXPECT_LE(c.max_penetration, penetration * (1.0 + 1e-9));
    std::printf("[sim3d] %s, %s, nu %.2f, level %d: F = %.5g N vs axisymmetric %.5g N: %+.2f%%, %.1f s\n",
                element.c_str(), stick ? "stick" : "frictionless", nu, level, row.force.back(), row.reference,
                100.0 * (row.force.back() / row.reference - 1.0), c.seconds);
  }
  return row;
}

TEST(Indentation3d, FlatPunchOnTheAxisymmetricGridSweptApproachesTheAxisymmetricForce) {
  // Linear tets are stiffer than the axisymmetric quads on the same grid and,
  // at ν 0.3, converge from above (measured at levels 0, 1, 2: frictionless
  // +11.2%, +7.3%, +3.7%; stick +11.0%, +4.2%, +1.6%; level 2 takes 2.5
  // minutes and is left to bench/).
  for (const auto contact : {axisym::PunchContact::Frictionless, axisym::PunchContact::Stick}) {
    const bool stick = contact == axisym::PunchContact::Stick;
    const PunchRow row = flat_punch(0.3, contact, 2);
    const double e0 = row.force[0] / row.reference - 1.0, e1 = row.force[1] / row.reference - 1.0;
    EXPECT_GT(e1, 0.0) << stick;
    EXPECT_LT(e1, stick ? 0.05 : 0.08) << stick;
    EXPECT_LT(e1, (stick ? 0.45 : 0.7) * e0) << stick;
  }
  // ν 0.45, frictionless: linear tets lock (+20% at level 0), and refined the
  // error changes sign (measured +20.4%, +0.5%, −2.7% at levels 0, 1, 2): it is
  // one-signed again only with an element that does not lock.
  const PunchRow firm = flat_punch(0.45, axisym::PunchContact::Frictionless, 2);
  const double e0 = firm.force[0] / firm.reference - 1.0, e1 = firm.force[1] / firm.reference - 1.0;
  EXPECT_LT(std::abs(e1), 0.03);
  EXPECT_LT(std::abs(e1), 0.25 * std::abs(e0));
}

TEST(Indentation3d, ConfinedLayerUnderAStuckPunchMatchesPokeWithNodalPressure) {
  // A 4 mm punch bonded to a 2 mm layer (radius 16 mm) pressed 0.1 mm: the
  // layer, confined between punch and base, is as stiff as its volume change
  // lets it be. Against `palpa poke` (level 4; level 5 is 0.3% softer),
  // measured with the nodal-pressure tet at levels 0–3: ν 0.49 +27.2%, +9.3%,
  // +3.20%, +0.99% (level 3: 450 s); ν 0.45 +13.9%, +5.2%, +1.78%. Stabilized
  // (β 0.2), ν 0.49: +65.7%, +24.3%. The linear tet, ν 0.49: +137% at level
  // 0; from level 1 its stuck rim keeps penetrating past 1 µm.
  const Layer confined{4e-3, 2e-3, 16e-3, 1e-4, 0.01};
  const PunchRow firm = flat_punch(0.45, axisym::PunchContact::Stick, 3, R"("element": "nodal-pressure", "stabilization": 0)", 2, confined);
  EXPECT_LT(std::abs(firm.force[0] / firm.reference - 1.0), 0.02);
  const PunchRow averaged = flat_punch(0.49, axisym::PunchContact::Stick, 3, R"("element": "nodal-pressure", "stabilization": 0)", 2, confined);
  EXPECT_GT(averaged.force[0] / averaged.reference - 1.0, 0.0);
  EXPECT_LT(averaged.force[0] / averaged.reference - 1.0, 0.04);
  const PunchRow linear = flat_punch(0.49, axisym::PunchContact::Stick, 1, R"("element": "linear")", 0, confined);
  EXPECT_GT(linear.force[0] / linear.reference - 1.0, 0.3);
}

// A rigid sphere of radius R pressed d into a layer of thickness h bonded to
// a rigid base: the force over Hertz's half-space force, with the layer's
// correction in χ = √(Rd)/h to fourth order (Dimitriadis et al. 2002, Biophys.
// J. 82, eq. 9–11; exact in ν for χ ≲ 0.3).
double bonded_layer_factor(double nu, double chi) {
  constexpr double pi = std::numbers::pi;
  const double a0 = -(1.2876 - 1.4678 * nu + 1.3442 * nu * nu) / (1.0 - nu);
  const double b0 = (0.6387 - 1.0277 * nu + 1.5164 * nu * nu) / (1.0 - nu);
  return 1.0 - 2.0 * a0 / pi * chi + 4.0 * a0 * a0 / (pi * pi) * chi * chi -
         8.0 / (pi * pi * pi) * (a0 * a0 * a0 + 4.0 * pi * pi / 15.0 * b0) * chi * chi * chi +
         16.0 * a0 / (pi * pi * pi * pi) * (a0 * a0 * a0 + 3.0 * pi * pi / 5.0 * b0) * chi * chi * chi * chi;
}

struct HertzCase {
  double nu = 0.49;
  std::string element = R"("element": "nodal-pressure", "stabilization": 0)";
  int level = 1, segments = 48, sphere_level = 6;
  double sphere = 20e-3, depth = 0.2e-3, thickness = 60e-3, radius = 60e-3;
  std::string sampling = "vertices";
};

struct HertzResult {
  double force = 0.0, force_error = 0.0, radius_error = 0.0, profile_rms = 0.0, seconds = 0.0;
};

// The sphere against Hertz: the force (with the layer's correction), the
// contact radius from the pressure's second moment (a² = 5/2 ∫p r² / ∫p for
// p0 √(1 − r²/a²)), and the RMS over p0 of the vertex pressures within 1.2 a
// against Hertz's traction recovered the way palpa recovers its own: a
// vertex's consistent load ∫ N_v p dA over its share of the deformed skin
// (what a mat whose cells are the vertices' shares would read; at the contact's
// edge, where p falls as a square root, a cell's mean is about 2.5× the point
// value at its centre). The RMS against the point values is printed too.
HertzResult hertz(const HertzCase& k) {
  const double a = std::sqrt(k.sphere * k.depth);
  ScratchDir dir;
  PunchScene p;
  p.body = fmt::format(R"("cylinder": {{"radius": "{} mm", "height": "{} mm", "rim": "{} mm", "level": {},
                                        "segments": {}, "sector": "90 deg"}}, {})",
                       k.radius * 1e3, k.thickness * 1e3, a * 1e3, k.level, k.segments, k.element);
  p.fixed = R"([{"set": "bottom"}, {"set": "sector_start", "components": "y"},
                {"set": "sector_end", "components": "x"}])";
  p.material = fmt::format(R"({{"model": "neo-hookean", "parameters": {{"E": "10 kPa", "nu": {}}}}})", k.nu);
  p.shape = fmt::format(R"({{"sphere": {{"radius": "{} mm", "level": {}}}}})", k.sphere * 1e3, k.sphere_level);
  p.depth = fmt::format("{} mm", k.depth * 1e3);
  p.steps = 2;
  p.contact = fmt::format(R"({{"max_penetration": "{} mm", "sampling": "{}"}})", 1e-3 * k.depth * 1e3, k.sampling);
  const Scene scene = read_scene(write_punch_scene(dir, p));
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(scene);
  StepRecord r;
  for (int s = 1; s <= scene.steps; ++s) r = sim.solve_step(s);
  HertzResult out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double E = 10e3, Es = E / (1.0 - k.nu * k.nu);
  const double hertz_force = 4.0 / 3.0 * Es * std::sqrt(k.sphere) * std::pow(k.depth, 1.5);
  out.force = 4.0 * r.obstacles[0].indentation_force;
  out.force_error = out.force / (hertz_force * bonded_layer_factor(k.nu, a / k.thickness)) - 1.0;
  const Eigen::VectorXd x = sim.system().positions(sim.displacement());
  const Eigen::VectorXd pressure = sim.contact_term(0).pressures(x);
  const Eigen::MatrixX3d deformed = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(x.data(), x.size() / 3, 3);
  const Eigen::VectorXd area = geometry::vertex_areas(deformed, sim.contact_term(0).faces());
  double m0 = 0.0, m2 = 0.0;
  for (Eigen::Index v = 0; v < pressure.size(); ++v) {
    const double r2 = x[3 * v] * x[3 * v] + x[3 * v + 1] * x[3 * v + 1];
    m0 += pressure[v] * area[v];
    m2 += pressure[v] * area[v] * r2;
  }
  out.radius_error = std::sqrt(2.5 * m2 / m0) / a - 1.0;
  const double p0 = 2.0 * Es * a / (std::numbers::pi * k.sphere);
  const auto hertz_p = [&](const Eigen::Vector3d& q) {
    const double r2 = q.x() * q.x() + q.y() * q.y();
    return r2 < a * a ? p0 * std::sqrt(1.0 - r2 / (a * a)) : 0.0;
  };
  const Eigen::MatrixX3i& faces = sim.contact_term(0).faces();
  const contact::TriangleRule rule = contact::subdivision_rule(16);
  Eigen::VectorXd load = Eigen::VectorXd::Zero(pressure.size());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d A = deformed.row(faces(f, 0)), B = deformed.row(faces(f, 1)), C = deformed.row(faces(f, 2));
    const double area_f = 0.5 * (B - A).cross(C - A).norm();
    for (std::size_t q = 0; q < rule.weight.size(); ++q) {
      const Eigen::Vector3d& b = rule.barycentric[q];
      const double w = rule.weight[q] * area_f * hertz_p(b[0] * A + b[1] * B + b[2] * C);
      for (int c = 0; c < 3; ++c) load[faces(f, c)] += b[c] * w;
    }
  }
  double sum = 0.0, point_sum = 0.0;
  int n = 0;
  const auto& surface = sim.contact_term(0).surface();
  for (const int v : surface) {
    const double rr = std::hypot(x[3 * v], x[3 * v + 1]);
    // Vertices on the quarter's cut planes share their skin with the planes.
    if (rr > 1.2 * a || x[3 * v + 2] < -5.0 * k.depth || std::min(std::abs(x[3 * v]), std::abs(x[3 * v + 1])) < 1e-9) {
      continue;
    }
    const double recovered = load[v] / area[v];
    sum += (pressure[v] - recovered) * (pressure[v] - recovered);
    const double point = hertz_p(deformed.row(v).transpose());
    point_sum += (pressure[v] - point) * (pressure[v] - point);
    ++n;
  }
  out.profile_rms = std::sqrt(sum / std::max(n, 1)) / p0;
  std::printf("[sim3d] Hertz, %s, nu %.2f, level %d, %d segments: F %.5g N (%+.2f%% of %.5g N with the layer's "
              "%+.2f%%), a %+.2f%%, p(r) RMS %.2f%% of p0 over %d vertices (%.2f%% against point values), %.1f s\n",
              k.element.c_str(), k.nu, k.level, k.segments, out.force, 100.0 * out.force_error,
              hertz_force * bonded_layer_factor(k.nu, a / k.thickness),
              100.0 * (bonded_layer_factor(k.nu, a / k.thickness) - 1.0), 100.0 * out.radius_error,
              100.0 * out.profile_rms, n, 100.0 * std::sqrt(point_sum / std::max(n, 1)) / p0, out.seconds);
  return out;
}

TEST(Indentation3d, HertzSphereOnANearlyIncompressibleBlock) {
  // A 20 mm sphere 0.2 mm into a 60 mm block (a = 2 mm, χ = a/h = 0.033), a
  // quarter at level 1 with 48 segments, springs at the vertices. Measured
  // with the unstabilized nodal-pressure tet at ν 0.49: F −1.43%, a +1.40%,
  // p(r) RMS 2.71% of p0 (3.82% against Hertz's point values, the contact
  // edge's ring most); with the default stabilization 0.1: F −0.63%, a +1.04%,
  // RMS 3.59% (the per-tet share of the volume change roughens the pressure).
  // The linear tet locks: at level 0, ν 0.49, F +23.8%.
  HertzCase k;
  const HertzResult r = hertz(k);
  EXPECT_LT(std::abs(r.force_error), 0.02);
  EXPECT_LT(std::abs(r.radius_error), 0.02);
  EXPECT_LT(r.profile_rms, 0.03);
  HertzCase linear;
  linear.element = R"("element": "linear")";
  linear.level = 0;
  EXPECT_GT(hertz(linear).force_error, 0.1);
}

TEST(Indentation3d, SquareIndenterForceIsMonotoneWithBoundedPenetration) {
  ScratchDir dir;
  PunchScene p;
  p.size_mm = R"(["30 mm", "30 mm", "10 mm"])";
  p.cells = "[12, 12, 4]";
  p.shape = R"({"box": {"size": ["8 mm", "8 mm", "5 mm"], "divisions": 4}})";
  p.depth = "3 mm";
  p.steps = 6;
  p.contact = R"({"max_penetration": "0.02 mm"})";
  const Curve c = simulate(read_scene(write_punch_scene(dir, p)));
  for (std::size_t i = 1; i < c.force.size(); ++i) EXPECT_GT(c.force[i], c.force[i - 1]) << i;
  EXPECT_GT(c.force.front(), 0.0);
  EXPECT_LE(c.max_penetration, 0.02e-3);
  EXPECT_GT(c.min_det_f, 0.0);
  EXPECT_GE(c.min_contacts, 9);
}

TEST(Indentation3d, LocalPokeMatchesTheFullBlock) {
  // A 4 mm punch 1 mm into an 80 × 80 × 10 mm block: the full block vs the
  // tets within 10 mm of the punch with the cut held fixed.
  ScratchDir dir;
  PunchScene p;
  p.size_mm = R"(["80 mm", "80 mm", "10 mm"])";
  p.cells = "[32, 32, 4]";
  p.shape = R"({"cylinder": {"radius": "4 mm", "height": "10 mm", "segments": 48}})";
  p.depth = "1 mm";
  p.steps = 2;
  p.contact = R"({"max_penetration": "0.01 mm"})";
  const Curve full = simulate(read_scene(write_punch_scene(dir, p)));
  p.extra = R"(, "local": {"margin": "10 mm"})";
  const Scene ls = read_scene(write_punch_scene(dir, p, "local.json"));
  Simulation probe(ls);
  const double kept = static_cast<double>(probe.model().num_elements()) / static_cast<double>(ls.mesh.T.rows());
  const Curve local = simulate(ls);
  const double error = std::abs(local.force.back() - full.force.back()) / full.force.back();
  std::printf("[sim3d] local poke: %.1f%% of the tets, force %.5g vs %.5g N (%.2f%%), %.2f s vs %.2f s\n",
              100.0 * kept, local.force.back(), full.force.back(), 100.0 * error, local.seconds, full.seconds);
  EXPECT_LT(kept, 0.3);
  EXPECT_LT(error, 0.05);
}

}  // namespace
}  // namespace palpa::sim3d
