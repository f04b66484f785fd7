// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "model_fixtures.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/models.hpp"

namespace palpa::material {
namespace {

using palpa::test::ScratchDir;
using palpa::test::throws_error;

TEST(MaterialFile, EveryModelRoundTripsExactly) {
  ScratchDir dir;
  for (const auto& c : test::all_model_cases()) {
    const auto m = c.make();
    const auto path = dir / (c.name + ".json");
    Provenance prov = make_provenance("test");
    prov.objective = 1.25e-3;
    write_material_file(path, *m, prov);
    const MaterialFile back = read_material_file(path);
    EXPECT_EQ(back.material->model(), m->model()) << c.name;
    ASSERT_EQ(back.material->num_params(), m->num_params()) << c.name;
    EXPECT_EQ(back.material->params(), m->params()) << c.name;  // bit-exact
    const Vec3 l(1.2, 0.8, 1.05);
    EXPECT_EQ(back.material->psi(l), m->psi(l)) << c.name;
    EXPECT_EQ(back.provenance.method, "test");
    ASSERT_TRUE(back.provenance.objective.has_value());
    EXPECT_EQ(*back.provenance.objective, 1.25e-3);
  }
}

TEST(MaterialFile, ParametersAreWrittenWithUnits) {
  const Json j = material_to_json(NeoHookean(12e3, 0.45));
  EXPECT_EQ(j["model"], "neo-hookean");
  EXPECT_EQ(j["parameters"]["E"], "12 kPa");
  EXPECT_EQ(j["parameters"]["nu"], 0.45);
  const Json mr = material_to_json(IsochoricInvariant::mooney_rivlin(1500.0, 400.0, 2e-5));
  EXPECT_EQ(mr["parameters"]["C10"], "1.5 kPa");
  // 2e-5 is not exactly 20 · 1e-6 in binary: written in SI to stay exact.
  EXPECT_EQ(mr["parameters"]["D1"], "2e-05 1/Pa");
  EXPECT_EQ(material_to_json(IsochoricInvariant::neo_hookean(1e3, 0.5e-3))["parameters"]["D1"],
            "500 1/MPa");
}

TEST(MaterialFile, ReadsUserWrittenFile) {
  ScratchDir dir;
  const auto p = dir.write("m.json", R"({"model": "ogden",
      "parameters": {"mu": ["6.05 kPa", "-0.5 kPa"], "alpha": [4.7, -2], "nu": 0.45}})");
  const MaterialFile f = read_material_file(p);
  EXPECT_EQ(f.material->model(), "ogden");
  EXPECT_DOUBLE_EQ(f.material->params()[0], 6050.0);
  EXPECT_DOUBLE_EQ(f.material->params()[3], -2.0);
}

TEST(MaterialFile, TheIsochoricNeoHookeanReadsFromYoungAndPoisson) {
  ScratchDir dir;
  const auto p = dir.write("m.json", R"({"model": "neo-hookean-isochoric", "parameters": {"E": "13 kPa", "nu": 0.3}})");
  const MaterialFile f = read_material_file(p);
  EXPECT_NEAR(f.material->params()[0], 2500.0, 1e-9);
  // Written back in its own parameters.
  EXPECT_TRUE(material_to_json(*f.material)["parameters"].contains("C10"));
  const auto mixed = dir.write("x.json", R"({"model": "neo-hookean-isochoric", "parameters": {"E": "13 kPa", "nu": 0.3,
      "C10": "1 kPa"}})");
  EXPECT_TRUE(throws_error([&] { read_material_file(mixed); }, ErrorKind::Input, {"x.json", "C10 with E"}));
}

struct BadCase {
  std::string name;
  std::string content;
  std::vector<std::string> fragments;
};

// Written inline (a scene's "material"), a material refuses keys it does
// not know, as its file does.
TEST(MaterialFile, AnInlineMaterialRefusesUnknownKeys) {
  const Json j = Json::parse(R"({"material": {"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.4},
                                               "zzz": 1}})");
  EXPECT_TRUE(throws_error([&] { (void)material_from_json(JsonView(j, "scene.json").at("material")); },
                           ErrorKind::Input, {"scene.json", "material.zzz", "not a known field"}));
}

TEST(MaterialFile, BadFilesGetClearMessages) {
  const std::vector<BadCase> cases = {
      {"unknown_model", R"({"model": "rubber", "parameters": {}})",
       {"field 'model'", "unknown model 'rubber'", "neo-hookean"}},
      {"missing_param", R"({"model": "neo-hookean", "parameters": {"E": "10 kPa"}})",
       {"field 'parameters.nu'", "missing"}},
      {"unknown_param", R"({"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.4, "poisson": 0.4}})",
       {"field 'parameters.poisson'", "not a known field"}},
      {"negative_E", R"({"model": "neo-hookean", "parameters": {"E": "-10 kPa", "nu": 0.4}})",
       {"field 'parameters'", "E = -10000 must be positive"}},
      {"zero_E", R"({"model": "stvk", "parameters": {"E": "0 Pa", "nu": 0.4}})",
       {"must be positive"}},
      {"nu_half", R"({"model": "neo-hookean", "parameters": {"E": "10 kPa", "nu": 0.5}})",
       {"Poisson's ratio nu = 0.5", "(-1, 0.5)"}},
      {"nu_minus_one", R"({"model": "corotational", "parameters": {"E": "10 kPa", "nu": -1.0}})",
       {"outside (-1, 0.5)"}},
      {"no_unit", R"({"model": "neo-hookean", "parameters": {"E": 10000, "nu": 0.4}})",
       {"field 'parameters.E'", "has no unit"}},
      {"wrong_unit", R"({"model": "neo-hookean", "parameters": {"E": "10 mm", "nu": 0.4}})",
       {"is a length, not a pressure"}},
      {"nan", R"({"model": "neo-hookean", "parameters": {"E": "nan kPa", "nu": 0.4}})",
       {"field 'parameters.E'", "not a finite number"}},
      {"knots", R"({"model": "spline", "parameters": {
          "f": {"knots": [0.5, 1.5, 1.0], "values_Pa": [0, 0, 0]},
          "g": {"knots": [0.5, 1.0, 2.0], "values_Pa": [0, 0, 0]},
          "h": {"knots": [0.5, 1.0, 2.0], "values_Pa": [0, 0, 0]}}})",
       {"field 'parameters.f'", "not increasing"}},
      {"mismatch", R"({"model": "ogden", "parameters": {"mu": ["1 kPa"], "alpha": [2, 3], "nu": 0.4}})",
       {"as many mu as alpha"}},
      {"d1", R"({"model": "mooney-rivlin", "parameters": {"C10": "1 kPa", "C01": "0 kPa", "D1": "0 1/Pa"}})",
       {"D1", "must be positive"}},
      {"not_object", R"([1, 2])", {"not a JSON object"}},
      {"version", R"({"palpa_material": 7, "model": "neo-hookean", "parameters": {}})",
       {"format version 7"}},
  };
  ScratchDir dir;
  for (const auto& c : cases) {
    const auto p = dir.write(c.name + ".json", c.content);
    std::vector<std::string> frags = c.fragments;
    frags.push_back(c.name + ".json");
    EXPECT_TRUE(throws_error([&] { read_material_file(p); }, ErrorKind::Input, frags)) << c.name;
  }
}

}  // namespace
}  // namespace palpa::material
