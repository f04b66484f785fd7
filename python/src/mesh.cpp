// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa.read_mesh / write_mesh: surface and tet meshes as numpy arrays.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/mesh.hpp"

namespace palpa::python {

void bind_mesh(py::module_& m) {
  m.def(
      "read_mesh",
      [](const std::filesystem::path& path, const py::handle& unit) {
        MeshReadOptions o;
        o.unit_to_si = quantity_arg(unit, Dimension::Length, "unit");
        if (!(o.unit_to_si > 0.0)) throw_input_error("a unit of zero length", ErrorContext{"", 0, 0, "unit"}, "'m', 'mm', ...");
        py::tuple out(2);
        if (mesh_kind_of(path) == MeshKind::Tet) {
          TetMesh t;
          {
            py::gil_scoped_release release;
            t = read_tet_mesh(path, o);
          }
          out[0] = to_numpy(Eigen::MatrixXd(t.V));
          out[1] = to_numpy(Eigen::MatrixXi(t.T));
        } else {
          SurfaceMesh s;
          {
            py::gil_scoped_release release;
            s = read_surface_mesh(path, o);
          }
          out[0] = to_numpy(Eigen::MatrixXd(s.V));
          out[1] = to_numpy(Eigen::MatrixXi(s.F));
        }
        return out;
      },
      py::arg("path"), py::arg("unit") = "1 m",
      "Reads a surface (.obj .ply .stl .off .vtu) or tet mesh (.vtu .msh .node): (V, F) or (V, T), V float64 "
      "(n, 3) in metres (`unit`: the length of one file unit, e.g. '1 mm'), F (m, 3) or T (m, 4) int64.");
  m.def(
      "write_mesh",
      [](const std::filesystem::path& path, const py::handle& vertices, const py::handle& cells) {
        const Eigen::MatrixXd v = float_matrix(vertices, 3, "V");
        const py::array c = py::array::ensure(cells);
        if (!c || c.ndim() != 2 || (c.shape(1) != 3 && c.shape(1) != 4)) {
          throw_input_error("cells that are neither triangles nor tetrahedra", ErrorContext{"", 0, 0, "cells"},
                            "an (m, 3) array of triangles or an (m, 4) array of tetrahedra");
        }
        if (c.shape(1) == 3) {
          SurfaceMesh s{v, index_matrix(cells, 3, v.rows(), "F")};
          py::gil_scoped_release release;
          write_surface_mesh(path, s);
        } else {
          TetMesh t;
          t.V = v;
          t.T = index_matrix(cells, 4, v.rows(), "T");
          py::gil_scoped_release release;
          write_tet_mesh(path, t);
        }
      },
      py::arg("path"), py::arg("V"), py::arg("cells"),
      "Writes a surface mesh (cells (m, 3)) or tet mesh (cells (m, 4)) in the format of the file's extension, "
      "atomically; V in metres.");
}

}  // namespace palpa::python
