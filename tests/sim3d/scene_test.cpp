// SPDX-License-Identifier: AGPL-3.0-or-later
// Scenes: reading and refusing bad ones, and running with interruption and
// resume (bit-identical to an uninterrupted run).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "common/test_support.hpp"
#include "palpa/core/json.hpp"
#include "palpa/io/csv.hpp"
#include "palpa/io/mesh.hpp"
#include "palpa/sim3d/run.hpp"
#include "palpa/sim3d/scene.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"
#include "scene_fixtures.hpp"

namespace palpa::sim3d {
namespace {

using palpa::test::ScratchDir;
using palpa::test::throws_error;
using test::PunchScene;
using test::write_punch_scene;

TEST(Scene, ReadsABoxScene) {
  ScratchDir dir;
  const Scene s = read_scene(write_punch_scene(dir, PunchScene{}));
  EXPECT_EQ(s.mesh.T.rows(), 6 * 8 * 8 * 3);
  EXPECT_EQ(s.fixed.size(), 1u);
  EXPECT_EQ(s.fixed[0].vertices.size(), 81u);
  ASSERT_EQ(s.obstacles.size(), 1u);
  EXPECT_TRUE(s.obstacles[0].has_path);
  EXPECT_DOUBLE_EQ(s.obstacles[0].depth, 1e-3);
  EXPECT_DOUBLE_EQ(s.contact.max_penetration, 5e-5);
  EXPECT_EQ(s.steps, 4);
  // The box's top face is at z = 0, centred.
  EXPECT_DOUBLE_EQ(s.mesh.V.col(2).maxCoeff(), 0.0);
  EXPECT_DOUBLE_EQ(s.mesh.V.col(0).minCoeff(), -0.02);
}

TEST(Scene, ReadsACylinderWithARingOfNodesAtTheRim) {
  ScratchDir dir;
  PunchScene p;
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16,
                            "sector": "90 deg"})";
  p.fixed = R"([{"set": "bottom"}, {"set": "sector_start", "components": "y"},
                {"set": "sector_end", "components": "x"}])";
  const Scene s = read_scene(write_punch_scene(dir, p));
  ASSERT_EQ(s.fixed.size(), 3u);
  EXPECT_EQ(s.fixed[1].components, (std::array<bool, 3>{false, true, false}));
  for (int v : s.fixed[1].vertices) EXPECT_EQ(s.mesh.V(v, 1), 0.0);
  for (int v : s.fixed[2].vertices) EXPECT_NEAR(s.mesh.V(v, 0), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(s.mesh.V.col(2).maxCoeff(), 0.0);
  EXPECT_DOUBLE_EQ(s.mesh.V.col(2).minCoeff(), -0.01);
  // Five nodes (a quarter of 16 segments, both ends) on the rim in the top face.
  int on_rim = 0;
  for (Eigen::Index v = 0; v < s.mesh.V.rows(); ++v) {
    if (s.mesh.V(v, 2) == 0.0 && std::abs(s.mesh.V.row(v).head<2>().norm() - 0.004) < 1e-15) ++on_rim;
  }
  EXPECT_EQ(on_rim, 5);

  p.body = R"("cylinder": {"radius": "5 mm", "height": "10 mm", "rim": "4 mm"})";
  p.fixed = R"([{"set": "bottom"}])";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.cylinder.rim", "not well inside the radius 5 mm"}));
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "segments": 10, "sector": "90 deg"})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.cylinder.sector", "not a whole number of segments"}));
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 9})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.cylinder.level", "0 to 4"}));
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm"}, "box": {"size": ["1 mm", "1 mm", "1 mm"], "cells": [1, 1, 1]})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"more than one of \"box\", \"cylinder\""}));
  // The element, by name; the default is the stabilized nodal-pressure tet.
  p.fixed = R"([{"set": "bottom"}])";
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16})";
  const tet::ElementChoice by_default = read_scene(write_punch_scene(dir, p)).element;
  EXPECT_EQ(by_default.element, tet::TetElement::NodalPressure);
  EXPECT_EQ(by_default.stabilization, tet::kDefaultStabilization);
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "nodal-pressure")";
  EXPECT_EQ(read_scene(write_punch_scene(dir, p)).element.stabilization, tet::kDefaultStabilization);
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "linear")";
  const tet::ElementChoice linear = read_scene(write_punch_scene(dir, p)).element;
  EXPECT_EQ(linear.element, tet::TetElement::Linear);
  EXPECT_EQ(linear.stabilization, 0.0);
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "quadratic")";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.element", "unknown element 'quadratic'", "\"nodal-pressure\""}));
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "nodal-pressure", "stabilization": 0.25)";
  EXPECT_EQ(read_scene(write_punch_scene(dir, p)).element.stabilization, 0.25);
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "nodal-pressure", "stabilization": 1)";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.stabilization", "outside [0, 1)"}));
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16}, "element": "linear", "stabilization": 0.1)";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.stabilization", "\"linear\""}));
  // A whole cylinder has no cut planes.
  p.body = R"("cylinder": {"radius": "20 mm", "height": "10 mm", "rim": "4 mm", "level": 0, "segments": 16})";
  p.fixed = R"([{"set": "sector_start"}])";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"unknown vertex set 'sector_start'", "side"}));
}

TEST(Scene, RefusesUnknownSetsMembersAndRegionsWithoutMaterial) {
  ScratchDir dir;
  PunchScene p;
  p.extra = R"(, "gravty": ["0 m/s^2", "0 m/s^2", "-9.81 m/s^2"])";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input, {"gravty"}));

  // Contact sampling: the two kinds, and a surface stiffness per depth.
  p = PunchScene{};
  p.contact = R"({"sampling": "faces"})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"contact.sampling", "unknown contact sampling 'faces'", "\"surface\""}));
  p.contact = R"({"sampling": "surface", "subdivisions": 9})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input, {"contact.subdivisions"}));
  p.contact = R"({"sampling": "surface", "stiffness": "2000 N/m"})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"contact.stiffness", "Pa/m"}));
  p.contact = R"({"sampling": "surface", "friction": "coulomb"})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"contact.friction", "unknown friction 'coulomb'", "\"stick\""}));
  p.contact = R"({"sampling": "surface", "subdivisions": 3, "stiffness": "50 kPa/mm"})";
  const Scene surface = read_scene(write_punch_scene(dir, p));
  EXPECT_EQ(surface.contact.sampling, body::ContactSampling::Surface);
  EXPECT_EQ(surface.contact.subdivisions, 3);
  EXPECT_DOUBLE_EQ(surface.contact.stiffness, 5e7);

  std::string text = test::punch_scene_json(PunchScene{});
  text.replace(text.find("\"bottom\""), 8, "\"floor\"");
  const auto file = dir.write("floor.json", text);
  EXPECT_TRUE(throws_error([&] { read_scene(file); }, ErrorKind::Input,
                           {"floor.json", "body.fixed[0].set", "unknown vertex set 'floor'", "bottom"}));

  // A mesh file with two regions, a material for region 0 only.
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-0.01, -0.01, -0.01), Eigen::Vector3d(0.01, 0.01, 0.0),
                                        Eigen::Vector3i(2, 2, 2));
  box.mesh.region = Eigen::VectorXi::Zero(box.mesh.T.rows());
  box.mesh.region.tail(6).setOnes();
  write_tet_mesh(dir / "two.vtu", box.mesh);
  const auto two = dir.write("two.json", R"({"palpa_scene": 1, "body": {"mesh": "two.vtu",
      "materials": [{"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.3}}, "regions": [0]}],
      "fixed": [{"below": "-10 mm", "axis": "z"}]}})");
  EXPECT_TRUE(throws_error([&] { read_scene(two); }, ErrorKind::Input, {"two.json", "region 1", "has no material"}));
}

// A punch 10 mm high driven 100 mm in 2 steps into a 10 mm block would pass
// through it between two equilibria and report 0 N: refused, with the steps
// that would do; a step of just under half the thinner of the two is taken.
TEST(Scene, RefusesAStepThatCouldCarryAnObstacleThroughTheBody) {
  ScratchDir dir;
  PunchScene p;
  p.depth = "100 mm";
  p.steps = 2;
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"field 'steps'", "obstacle 'punch' moves 50 mm per step", "pass through the body",
                            "at least 20 steps"}));
  p.steps = 20;
  EXPECT_NO_THROW(read_scene(write_punch_scene(dir, p)));
  // The thinner one counts: a 2 mm-thick plate as the obstacle.
  p.shape = R"({"box": {"size": ["20 mm", "20 mm", "2 mm"]}})";
  p.depth = "4 mm";
  p.steps = 2;
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"moves 2 mm per step", "at least 4 steps"}));
  p.depth = "3.9 mm";
  p.steps = 4;
  EXPECT_NO_THROW(read_scene(write_punch_scene(dir, p)));
}

// Sizes that would not fit in memory or time are refused by field, before
// anything is built.
TEST(Scene, RefusesSizesBeyondWhatPalpaBuilds) {
  ScratchDir dir;
  PunchScene p;
  p.shape = R"({"cylinder": {"radius": "5 mm", "height": "10 mm", "segments": 100000000}})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"obstacles[0].shape.cylinder.segments", "100000000", "3 to 4096"}));
  p.shape = R"({"sphere": {"radius": "5 mm", "level": 20}})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"obstacles[0].shape.sphere.level", "0 to 7"}));
  p.shape = R"({"box": {"size": ["5 mm", "5 mm", "5 mm"], "divisions": 100000}})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"obstacles[0].shape.box.divisions", "1 to 500"}));
  p.shape = R"({"box": {"size": ["0 mm", "5 mm", "5 mm"]}})";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"scene.json", "obstacles[0].shape.box.size", "sizes must be > 0"}));
  p = PunchScene{};
  p.cells = "[1000, 1000, 1000]";
  EXPECT_TRUE(throws_error([&] { read_scene(write_punch_scene(dir, p)); }, ErrorKind::Input,
                           {"body.box.cells", "6e+09 tetrahedra", "at most 5000000"}));
}

TEST(Scene, RefusesInvertedTetsAndAnOpenObstacle) {
  ScratchDir dir;
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-0.01, -0.01, -0.01), Eigen::Vector3d(0.01, 0.01, 0.0),
                                        Eigen::Vector3i(2, 2, 2));
  std::swap(box.mesh.T(7, 0), box.mesh.T(7, 1));
  write_tet_mesh(dir / "bad.vtu", box.mesh);
  const auto bad = dir.write("bad.json", R"({"palpa_scene": 1, "body": {"mesh": "bad.vtu",
      "materials": [{"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.3}}}],
      "fixed": [{"set": "boundary"}]}})");
  EXPECT_TRUE(throws_error([&] { read_scene(bad); }, ErrorKind::Input, {"bad.vtu", "inverted", "tetrahedron 7"}));

  // A box surface with its top face missing is no solid.
  SurfaceMesh open = make_box_surface(Eigen::Vector3d(0.01, 0.01, 0.01), 1);
  SurfaceMesh cut;
  cut.V = open.V;
  cut.F.resize(open.F.rows() - 2, 3);
  Eigen::Index k = 0;
  for (Eigen::Index f = 0; f < open.F.rows(); ++f) {
    if (f == 2 || f == 3) continue;  // the z = top face's two triangles
    cut.F.row(k++) = open.F.row(f);
  }
  write_surface_mesh(dir / "open.obj", cut);
  PunchScene p;
  p.shape = R"({"file": "open.obj"})";
  const Scene s = read_scene(write_punch_scene(dir, p, "open.json"));
  EXPECT_TRUE(throws_error([&] { Simulation sim(s); }, ErrorKind::Input, {"obstacle 'punch'", "not closed"}));
}

class RunResume : public ::testing::TestWithParam<const char*> {};

TEST_P(RunResume, InterruptedAndResumedRunMatchesAnUninterruptedOne) {
  ScratchDir dir;
  PunchScene p;
  p.cells = "[4, 4, 2]";
  // On this coarsest box the stuck punch's centre vertex stays 19% past the
  // target penetration with the nodal-pressure tet; what is tested here is
  // the resume.
  p.element = R"(, "element": "linear")";
  // Stick contacts carry their anchors through the saved state.
  if (std::string(GetParam()) == "stick") p.contact = R"({"max_penetration": "0.05 mm", "sampling": "surface", "friction": "stick"})";
  const Scene s = read_scene(write_punch_scene(dir, p));
  RunOptions whole;
  whole.out = dir / "whole";
  whole.progress = Progress::Style::Silent;
  run(s, whole);
  const CsvTable a = read_csv(dir / "whole" / "force_punch.csv");
  EXPECT_FALSE(std::filesystem::exists(dir / "whole" / "state.json"));

  RunOptions part = whole;
  part.out = dir / "part";
  part.stop_after_steps = 2;
  EXPECT_TRUE(throws_error([&] { run(s, part); }, ErrorKind::Interrupted, {"stopped after 2 steps"}));
  EXPECT_TRUE(std::filesystem::exists(dir / "part" / "state.json"));
  EXPECT_EQ(read_csv(dir / "part" / "force_punch.csv").rows(), 3u);
  // Not without --resume …
  part.stop_after_steps = 0;
  EXPECT_TRUE(throws_error([&] { run(s, part); }, ErrorKind::Input, {"interrupted run", "--resume"}));
  part.resume = true;
  run(s, part);
  const CsvTable b = read_csv(dir / "part" / "force_punch.csv");
  ASSERT_EQ(a.rows(), b.rows());
  for (std::size_t i = 0; i < a.rows(); ++i) EXPECT_EQ(a.column("force_N")[i], b.column("force_N")[i]) << i;
  EXPECT_GT(a.column("force_N").back(), 0.0);
  EXPECT_FALSE(std::filesystem::exists(dir / "part" / "state.json"));
  const Json summary = read_json_file(dir / "part" / "summary.json");
  EXPECT_TRUE(summary.at("complete").get<bool>());
  EXPECT_EQ(summary.at("records").size(), 4u);
}

INSTANTIATE_TEST_SUITE_P(Friction, RunResume, ::testing::Values("frictionless", "stick"));

TEST(Run, TheDefaultPenetrationTargetIsASmallShareOfAShallowPoke) {
  ScratchDir dir;
  PunchScene p;
  p.contact = "{}";
  p.depth = "0.5 mm";
  const Scene shallow = read_scene(write_punch_scene(dir, p));
  const Simulation poke(shallow);
  EXPECT_DOUBLE_EQ(poke.target_penetration(), 0.01 * 0.5e-3);
  // Without a path, 2% of the mean surface edge (5 mm cells here).
  std::string text = test::punch_scene_json(p);
  text.replace(text.find(R"(, "path")"), 54, "");
  const Scene no_path = read_scene(dir.write("posed.json", text));
  const Simulation posed(no_path);
  EXPECT_GT(posed.target_penetration(), 0.02 * 2.5e-3);
  EXPECT_LT(posed.target_penetration(), 0.02 * 6e-3);
}

TEST(Run, AStepThatCannotConvergeKeepsTheStepsBeforeItAndNamesAVertex) {
  // The punch starts 0.5 mm above the block: step 1 stays 0.1 mm above it,
  // step 2 presses 0.3 mm with too few Newton iterations allowed.
  ScratchDir dir;
  PunchScene p;
  p.depth = "0.8 mm";
  p.steps = 2;
  p.extra = R"(, "solver": {"max_iterations": 2})";
  std::string text = test::punch_scene_json(p);
  text.replace(text.find(R"("shape")"), 7, R"("position": ["0 mm", "0 mm", "0.5 mm"], "shape")");
  const Scene s = read_scene(dir.write("scene.json", text));
  RunOptions o;
  o.out = dir / "out";
  o.progress = Progress::Style::Silent;
  EXPECT_TRUE(throws_error([&] { run(s, o); }, ErrorKind::Solver,
                           {"step 2 of 2", "did not converge", "largest unbalanced force", "at vertex", "mm)"}));
  const Json summary = read_json_file(o.out / "summary.json");
  EXPECT_FALSE(summary.at("complete").get<bool>());
  EXPECT_EQ(summary.at("steps_done").get<int>(), 1);
  EXPECT_EQ(summary.at("failed_step").get<int>(), 2);
  EXPECT_NE(summary.at("failure").get<std::string>().find("step 2 of 2"), std::string::npos);
  EXPECT_EQ(summary.at("records").size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(o.out / "force_punch.csv"));
}

TEST(Run, DampedDynamicsSettlesToTheStaticForce) {
  ScratchDir dir;
  PunchScene p;
  p.cells = "[4, 4, 2]";
  p.steps = 2;
  const Scene statics = read_scene(write_punch_scene(dir, p));
  p.extra = R"(, "dynamics": {"time_step": "20 ms", "mass_damping": "50 Hz", "max_steps": 2000, "settle": "1e-7 mm"})";
  const Scene dynamics = read_scene(write_punch_scene(dir, p, "dynamic.json"));
  ASSERT_TRUE(dynamics.dynamics.enabled);
  Simulation a(statics), b(dynamics);
  for (int s = 1; s <= 2; ++s) {
    const StepRecord ra = a.solve_step(s);
    const StepRecord rb = b.solve_step(s);
    EXPECT_GT(rb.solves, 2);  // several implicit steps
    EXPECT_NEAR(rb.obstacles[0].indentation_force, ra.obstacles[0].indentation_force,
                1e-4 * ra.obstacles[0].indentation_force)
        << s;
  }
}

}  // namespace
}  // namespace palpa::sim3d
