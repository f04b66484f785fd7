// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa._rest: `palpa rest` on a scene file or a scene given as JSON text,
// into an output folder; palpa.rest (the package) wraps it.

#include <fmt/format.h>

#include <filesystem>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/rest/output.hpp"
#include "palpa/rest/scene.hpp"

namespace palpa::python {

void bind_rest(py::module_& m) {
  m.def(
      "_rest",
      [](const std::string& scene, bool is_file, const std::string& base, const std::string& out, bool overwrite) {
        rest::RestRun run;
        {
          LongCall call;
          rest::RestScene s;
          if (is_file) {
            s = rest::read_rest_scene(scene);
          } else {
            Json doc;
            try {
              doc = Json::parse(scene);
            } catch (const std::exception& e) {
              throw_input_error(fmt::format("the scene is not JSON: {}", e.what()), ErrorContext{"", 0, 0, "scene"},
                                "a dict of a rest scene");
            }
            s = rest::read_rest_scene(doc, std::filesystem::path(base) / "scene (dict)");
          }
          run = rest::run_rest(s, out, overwrite);
        }
        py::dict d;
        d["body_pressure"] = to_numpy(run.result.body_pressure);
        d["support_pressure"] = to_numpy(run.result.support_pressure);
        d["skin_vertices"] = to_numpy(Eigen::MatrixXd(run.skin.V));
        d["skin_faces"] = to_numpy(Eigen::MatrixXi(run.skin.F));
        d["support_vertices"] = to_numpy(Eigen::MatrixXd(run.support.V));
        d["support_faces"] = to_numpy(Eigen::MatrixXi(run.support.F));
        d["summary"] = run.summary.dump();
        return d;
      },
      py::arg("scene"), py::arg("is_file"), py::arg("base"), py::arg("out"), py::arg("overwrite"),
      "Runs `palpa rest` into `out`. Use palpa.rest.");
}

}  // namespace palpa::python
