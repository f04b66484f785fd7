// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa._design: `palpa design` on a scene file or a scene given as JSON text,
// into an output folder; palpa.design (the package) wraps it.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/design/run.hpp"

namespace palpa::python {

void bind_design(py::module_& m) {
  m.def(
      "_design",
      [](const std::string& scene, bool is_file, const std::string& base, const std::string& out, bool resume,
         bool overwrite, bool baselines, std::optional<int> iterations, std::optional<int> threads,
         std::optional<std::string> method) -> py::object {
        design::DesignRun run;
        if (is_file) {
          run.scene = scene;
        } else {
          run.scene = std::filesystem::path(base) / "scene (dict)";
          try {
            run.scene_json = Json::parse(scene);
          } catch (const std::exception& e) {
            throw_input_error(fmt::format("the scene is not JSON: {}", e.what()), ErrorContext{"", 0, 0, "scene"},
                              "a dict of a design scene");
          }
        }
        run.out = out;
        run.resume = resume;
        run.overwrite = overwrite;
        run.baselines = baselines;
        if (iterations && *iterations < 0) {
          throw_input_error(fmt::format("{} iterations", *iterations), ErrorContext{"", 0, 0, "iterations"}, "0 or more");
        }
        if (threads && *threads < 0) {
          throw_input_error(fmt::format("{} threads", *threads), ErrorContext{"", 0, 0, "threads"}, "0 or more");
        }
        run.iterations = iterations;
        run.threads = threads;
        if (method) {
          if (*method == "lbfgs") {
            run.method = design::DesignMethod::Lbfgs;
          } else if (*method == "cg") {
            run.method = design::DesignMethod::ConjugateGradient;
          } else {
            throw_input_error(fmt::format("unknown method '{}'", *method), ErrorContext{"", 0, 0, "method"},
                              "lbfgs or cg");
          }
        }
        SurfaceMesh optimized;
        std::optional<Json> summary;
        {
          LongCall call;
          summary = design::run_design(run, &optimized);
        }
        if (!summary) return py::none();
        py::dict d;
        d["summary"] = summary->dump();
        d["support_vertices"] = to_numpy(Eigen::MatrixXd(optimized.V));
        d["support_faces"] = to_numpy(Eigen::MatrixXi(optimized.F));
        return d;
      },
      py::arg("scene"), py::arg("is_file"), py::arg("base"), py::arg("out"), py::arg("resume"), py::arg("overwrite"),
      py::arg("baselines"), py::arg("iterations"), py::arg("threads"), py::arg("method"),
      "Runs `palpa design` into `out`; None when a resumed run was already finished. Use palpa.design.");
}

}  // namespace palpa::python
