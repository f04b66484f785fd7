// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Datasets that must be refused, each with the files it needs and the message
// fragments that name the file, the field and the problem. Shared by the
// library test (dataset_test.cpp) and the command-line test (fit_cli_test.cpp).

#include <string>
#include <utility>
#include <vector>

namespace palpa::fit::test {

struct BadDataset {
  std::string what;
  std::string dataset;                                      // text of dataset.json
  std::vector<std::pair<std::string, std::string>> files;   // curve files (name, text)
  std::vector<std::string> fragments;                       // expected in the message
};

// A small valid curve (indentation in mm, force in N).
inline const char* const kGoodCurve = "indentation_mm,force_N\n0.25,0.01\n0.5,0.03\n0.75,0.055\n1.0,0.085\n";

// An indentation dataset with one training curve `file` (radius 3 mm, layer
// 10 mm, block 100 mm) unless the parts are replaced.
inline std::string indentation_dataset(const std::string& curves =
                                           R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                       const std::string& extra = R"("layer_depth": "10 mm")",
                                       const std::string& head = R"("palpa_dataset": 1, "test": "indentation")") {
  return "{" + head + ", " + extra + R"(, "lateral_size": "100 mm", "contact": "stick", "curves": )" + curves + "}";
}

inline std::vector<BadDataset> bad_datasets() {
  const std::string good = kGoodCurve;
  return {
      {"missing curve file", indentation_dataset(R"([{"file": "nope.csv", "radius": "3 mm", "role": "train"}])"),
       {}, {"dataset.json", "curves[0].file", "nope.csv", "does not exist"}},
      {"unknown format tag", indentation_dataset().replace(1, 18, R"("palpa_dataset": 2)"), {{"a.csv", good}},
       {"dataset.json", "palpa_dataset", "format 2"}},
      {"missing format tag", R"({"test": "indentation", "layer_depth": "10 mm", "contact": "stick", "curves": []})",
       {}, {"dataset.json", "missing \"palpa_dataset\""}},
      {"unknown member", indentation_dataset().replace(indentation_dataset().find("lateral_size"), 12, "lateral_sise"),
       {{"a.csv", good}}, {"dataset.json", "lateral_sise", "not a known field"}},
      {"unknown curve member",
       indentation_dataset(R"([{"file": "a.csv", "radious": "3 mm", "role": "train"}])"), {{"a.csv", good}},
       {"dataset.json", "curves[0].radious", "not a known field"}},
      {"two points", indentation_dataset(), {{"a.csv", "indentation_mm,force_N\n0.5,0.03\n1.0,0.085\n"}},
       {"a.csv", "2 points", "at least 3 points"}},
      {"indentation not increasing", indentation_dataset(),
       {{"a.csv", "indentation_mm,force_N\n0.25,0.01\n0.5,0.03\n0.5,0.04\n1.0,0.085\n"}},
       {"a.csv:4", "does not increase"}},
      {"negative force", indentation_dataset(),
       {{"a.csv", "indentation_mm,force_N\n0.25,0.01\n0.5,-0.003\n0.75,0.055\n1.0,0.085\n"}},
       {"a.csv:3", "column 'force_N'", "force -0.003 N is negative"}},
      {"punch as wide as half the block",
       indentation_dataset(R"([{"file": "a.csv", "radius": "50 mm", "role": "train"}])"), {{"a.csv", good}},
       {"dataset.json", "curves[0].radius", "half the sample's lateral size"}},
      {"no training curve", indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "validate"}])"),
       {{"a.csv", good}}, {"dataset.json", "curves", "no curve has role \"train\""}},
      {"mass as a length", indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                                               R"("layer_depth": "10 kg")"),
       {{"a.csv", good}}, {"dataset.json", "layer_depth", "10 kg"}},
      {"unknown role", indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "test"}])"),
       {{"a.csv", good}}, {"dataset.json", "curves[0].role", "unknown role 'test'"}},
      {"unknown contact",
       R"({"palpa_dataset": 1, "test": "indentation", "layer_depth": "10 mm", "contact": "glue",
           "curves": [{"file": "a.csv", "radius": "3 mm", "role": "train"}]})",
       {{"a.csv", good}}, {"dataset.json", "contact", "unknown punch contact 'glue'"}},
      {"unknown platen contact",
       R"({"palpa_dataset": 1, "test": "compression", "sample_radius": "10 mm", "sample_height": "10 mm",
           "contact": "stick", "curves": [{"file": "a.csv", "role": "train"}]})",
       {{"a.csv", good}}, {"dataset.json", "contact", "unknown platen contact 'stick'"}},
      {"unknown test", indentation_dataset().replace(indentation_dataset().find("\"indentation\""), 13, "\"poke\""),
       {{"a.csv", good}}, {"dataset.json", "test", "unknown test 'poke'"}},
      {"indentation to 90% of the layer",
       indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train"}])",
                           R"("layer_depth": "1.1 mm")"),
       {{"a.csv", good}}, {"dataset.json", "curves[0].file", "not below 90% of the layer depth"}},
      {"two curves with one name",
       indentation_dataset(R"([{"file": "A/r.csv", "radius": "3 mm", "role": "train"},
                               {"file": "B/r.csv", "radius": "2 mm", "role": "validate"}])"),
       {{"A/r.csv", good}, {"B/r.csv", good}},
       {"dataset.json", "curves[1].file", "curves 1", "and 2", "are both named 'r'", "a distinct \"name\""}},
      {"a name that is a path",
       indentation_dataset(R"([{"file": "a.csv", "radius": "3 mm", "role": "train", "name": "x/y"}])"),
       {{"a.csv", good}}, {"dataset.json", "curves[0].name", "curve name 'x/y' cannot name its output file"}},
  };
}

}  // namespace palpa::fit::test
