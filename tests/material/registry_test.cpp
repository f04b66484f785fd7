// SPDX-License-Identifier: AGPL-3.0-or-later
// The model registry: every model is built from its named parameters and gives
// them back; wrong keys, missing and mistyped parameters are refused by name.
#include <gtest/gtest.h>

#include <set>

#include "common/test_support.hpp"
#include "model_fixtures.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::material {
namespace {

using palpa::test::throws_error;

TEST(MaterialRegistry, EveryModelIsRebuiltFromItsNamedParameters) {
  std::set<std::string> covered;
  for (const auto& c : test::all_model_cases()) {
    const auto m = c.make();
    const ModelSpec& spec = model_spec(m->model());
    const ParameterValues values = parameter_values(*m);
    // The values carry exactly the model's keys.
    std::set<std::string> keys;
    for (const auto& p : spec.parameters) keys.emplace(p.key);
    const auto given = values.keys();
    EXPECT_EQ(std::set<std::string>(given.begin(), given.end()), keys) << c.name;
    const auto back = make_material(spec, values);
    EXPECT_EQ(back->model(), m->model()) << c.name;
    EXPECT_EQ(back->params(), m->params()) << c.name;  // bit-exact
    covered.emplace(m->model());
  }
  // The fixtures reach every model the registry knows.
  for (const auto& spec : models()) EXPECT_TRUE(covered.count(std::string(spec.name))) << spec.name;
}

TEST(MaterialRegistry, DefaultsFillOptionalParameters) {
  ParameterValues v;
  v.scalars = {{"E", 12e3}, {"nu", 0.45}};
  const auto m = make_material("neo-hookean-volume", v);
  EXPECT_EQ(m->params()[2], 0.5);
  v.scalars = {{"C10", 1e3}, {"D1", 1e-5}};
  const auto y = make_material("yeoh", v);
  EXPECT_EQ(y->params(), Eigen::Vector4d(1e3, 0.0, 0.0, 1e-5));
  EXPECT_EQ(model_spec("neo-hookean-volume").parameter_summary(), "E, nu, volume_share (default 0.5)");
  EXPECT_EQ(model_spec("ogden").parameter_summary(), "mu[], alpha[], nu");
}

TEST(MaterialRegistry, WrongParametersAreRefusedByName) {
  const auto spell = [](std::string_view key) { return "--" + std::string(key); };
  ParameterValues v;
  v.scalars = {{"E", 12e3}};
  EXPECT_TRUE(throws_error([&] { make_material("neo-hookean", v, {}, spell); }, ErrorKind::Input,
                           {"model 'neo-hookean' needs --nu"}));
  v.scalars = {{"E", 12e3}, {"nu", 0.3}, {"C10", 1e3}};
  EXPECT_TRUE(throws_error([&] { make_material("stvk", v, {}, spell); }, ErrorKind::Input,
                           {"--C10 does not apply to model 'stvk'", "--E, --nu"}));
  v.scalars = {{"nu", 0.3}, {"mu", 1e3}};
  v.lists = {{"alpha", {2.0}}};
  EXPECT_TRUE(throws_error([&] { make_material("ogden", v); }, ErrorKind::Input, {"mu is one value", "list"}));
  EXPECT_TRUE(throws_error([&] { make_material("rubber", v, ErrorContext{"", 0, 0, "option --model"}); },
                           ErrorKind::Input, {"unknown model 'rubber'", "option --model", "neo-hookean, "}));
  // Values the constructor refuses keep its message.
  v = {};
  v.scalars = {{"E", -1.0}, {"nu", 0.3}};
  EXPECT_TRUE(throws_error([&] { make_material("neo-hookean", v); }, ErrorKind::Input, {"must be positive"}));
}

TEST(MaterialRegistry, TheIsochoricNeoHookeanAlsoTakesYoungAndPoisson) {
  ParameterValues v;
  v.scalars = {{"E", 13e3}, {"nu", 0.3}};
  const auto m = make_material("neo-hookean-isochoric", v);
  // C10 = mu/2 = E / (4 (1 + nu)), D1 = 2/K = 6 (1 - 2 nu) / E.
  EXPECT_NEAR(m->params()[0], 13e3 / 5.2, 1e-9);
  EXPECT_NEAR(m->params()[1], 6.0 * 0.4 / 13e3, 1e-15);
  const auto spell = [](std::string_view key) { return "--" + std::string(key); };
  v.scalars = {{"E", 13e3}};
  EXPECT_TRUE(throws_error([&] { make_material("neo-hookean-isochoric", v, {}, spell); }, ErrorKind::Input,
                           {"needs --nu with --E", "--C10, --D1 or --E, --nu"}));
  v.scalars = {{"E", 13e3}, {"nu", 0.3}, {"D1", 1e-5}};
  EXPECT_TRUE(throws_error([&] { make_material("neo-hookean-isochoric", v, {}, spell); }, ErrorKind::Input,
                           {"--D1 with --E"}));
  EXPECT_EQ(model_spec("neo-hookean-isochoric").parameter_summary(), "C10, D1; or E, nu");
}

TEST(MaterialRegistry, OnlyModelsWithAFitAreFittable) {
  EXPECT_EQ(model_names(true),
            "neo-hookean, neo-hookean-volume, neo-hookean-isochoric, mooney-rivlin, yeoh, ogden, spline");
  EXPECT_NO_THROW(model_spec("yeoh", {}, true));
  EXPECT_TRUE(throws_error([] { model_spec("stvk", ErrorContext{"", 0, 0, "model"}, true); }, ErrorKind::Input,
                           {"model 'stvk' cannot be fitted", "one of: neo-hookean"}));
}

}  // namespace
}  // namespace palpa::material
