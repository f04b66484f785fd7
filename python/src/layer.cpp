// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa.mesh_layer: a soft tet layer on a rigid core from a scan, in memory
// (the meshing of `palpa mesh layer`).

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/mesh/layer.hpp"

namespace palpa::python {

namespace {

// Samples from an (n, 3) array of points [m] and n values, or None.
std::optional<mesh::Samples> samples_from(const py::handle& points, const py::handle& values, const char* name) {
  if (points.is_none() && values.is_none()) return std::nullopt;
  if (points.is_none() || values.is_none()) {
    throw_input_error(fmt::format("{} points without values or values without points", name),
                      ErrorContext{"", 0, 0, name}, "both the points (n, 3) [m] and their n values");
  }
  mesh::Samples s;
  s.positions = float_matrix(points, 3, (std::string(name) + "_points").c_str());
  s.values = float_vector(values, (std::string(name) + "_values").c_str());
  if (s.values.size() != s.positions.rows()) {
    throw_input_error(fmt::format("{} points and {} values", s.positions.rows(), s.values.size()),
                      ErrorContext{"", 0, 0, name}, "one value per point");
  }
  for (Eigen::Index i = 0; i < s.values.size(); ++i) s.labels.push_back(fmt::format("sample {}", i));
  s.source = fmt::format("{} (arrays)", name);
  s.field = name;
  return s;
}

}  // namespace

void bind_layer(py::module_& m) {
  m.def(
      "mesh_layer",
      [](const py::handle& vertices, const py::handle& faces, const py::handle& depth, const py::handle& depth_points,
         const py::handle& depth_values, const py::handle& stiffness_points, const py::handle& stiffness_values,
         const py::handle& edge, bool clamp_depth) {
        SurfaceMesh scan;
        scan.V = float_matrix(vertices, 3, "V");
        scan.F = index_matrix(faces, 3, scan.V.rows(), "F");
        mesh::DepthSpec d;
        d.samples = samples_from(depth_points, depth_values, "depth");
        if (!depth.is_none()) {
          if (d.samples) {
            throw_input_error("both a uniform depth and depth samples", ErrorContext{"", 0, 0, "depth"}, "one of them");
          }
          d.uniform = quantity_arg(depth, Dimension::Length, "depth");
          if (!(d.uniform > 0.0)) throw_input_error(format_quantity(d.uniform, Dimension::Length),
                                                    ErrorContext{"", 0, 0, "depth"}, "a positive length");
        } else if (!d.samples) {
          throw_input_error("no layer depth", ErrorContext{"", 0, 0, "depth"},
                            "depth= (e.g. '10 mm') or depth_points= and depth_values=");
        }
        const auto stiffness = samples_from(stiffness_points, stiffness_values, "stiffness");
        mesh::LayerOptions o;
        o.edge_length = quantity_arg(edge, Dimension::Length, "edge");
        if (!(o.edge_length > 0.0)) throw_input_error(format_quantity(o.edge_length, Dimension::Length),
                                                      ErrorContext{"", 0, 0, "edge"}, "a positive length");
        o.clamp_depth = clamp_depth;
        o.source = "the scan (arrays)";
        mesh::LayerMesh layer;
        {
          LongCall call;
          o.on_stage = [](std::string_view) { check_interrupt(); };
          layer = mesh::make_layer(scan, d, stiffness, o);
        }
        py::dict out;
        out["V"] = to_numpy(Eigen::MatrixXd(layer.tets.V));
        out["T"] = to_numpy(Eigen::MatrixXi(layer.tets.T));
        Eigen::MatrixXi attached(static_cast<Eigen::Index>(layer.attached.size()), 1);
        for (Eigen::Index i = 0; i < attached.rows(); ++i) attached(i, 0) = static_cast<int>(layer.attached[static_cast<std::size_t>(i)]);
        out["attached"] = to_numpy(attached).attr("ravel")();
        out["youngs_modulus"] = layer.youngs_modulus.size() ? py::object(to_numpy(layer.youngs_modulus)) : py::none();
        out["outer_vertices"] = to_numpy(Eigen::MatrixXd(layer.outer.V));
        out["outer_faces"] = to_numpy(Eigen::MatrixXi(layer.outer.F));
        out["core_vertices"] = to_numpy(Eigen::MatrixXd(layer.core.V));
        out["core_faces"] = to_numpy(Eigen::MatrixXi(layer.core.F));
        out["depth"] = to_numpy(layer.depth);
        return out;
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("depth") = py::none(), py::arg("depth_points") = py::none(),
      py::arg("depth_values") = py::none(), py::arg("stiffness_points") = py::none(),
      py::arg("stiffness_values") = py::none(), py::arg("edge") = "5 mm", py::arg("clamp_depth") = false,
      R"doc(Meshes the soft layer between a closed scan surface (V [m], F) and an inner surface at
`depth` (uniform, a length) or at depths interpolated from samples (depth_points (n, 3) [m],
depth_values [m]); optional stiffness samples (points, Young's moduli [Pa]) give each tet
its modulus. Returns a dict: V, T (the tets), attached (rows of V on the rigid core),
youngs_modulus (per tet or None), outer_vertices/faces, core_vertices/faces, depth (per
outer vertex). Releases the GIL; Ctrl-C raises KeyboardInterrupt between stages.)doc");
}

}  // namespace palpa::python
