// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What the parts of the Python module share: array conversion that never
// reads garbage, quantities given as floats (SI) or strings with units, and
// the scope of a long call (GIL released, Ctrl-C honoured).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <Eigen/Core>
#include <csignal>
#include <string>

#include "palpa/core/units.hpp"

namespace palpa::python {

namespace py = pybind11;

// An (n, cols) array of finite float64 values (cols 0: a 1-D array of n) from
// any numeric array-like: other dtypes, Fortran order and strided views are
// converted; booleans, complex numbers, objects and strings, another shape
// and NaN or infinity are refused (TypeError for the kind, palpa.InputError
// for the values), naming `name`. n may be 0 only if `allow_empty`.
Eigen::MatrixXd float_matrix(const py::handle& a, Eigen::Index cols, const char* name, bool allow_empty = false);
Eigen::VectorXd float_vector(const py::handle& a, const char* name, bool allow_empty = false);
// An (n, cols) array of non-negative integer indices below `bound`, from an
// integer array of any width (int32 faces too); floats are refused.
Eigen::MatrixXi index_matrix(const py::handle& a, Eigen::Index cols, Eigen::Index bound, const char* name);

// A numpy array that owns a copy of `m` (row-major (rows, cols); a vector
// gives a 1-D array).
py::array_t<double> to_numpy(const Eigen::MatrixXd& m);
py::array_t<double> to_numpy(const Eigen::VectorXd& v);
py::array_t<std::int64_t> to_numpy(const Eigen::MatrixXi& m);

// A physical value: a float or int in SI, or a string with a unit ("3 mm");
// an input error naming `name` otherwise.
double quantity_arg(const py::handle& value, Dimension d, const char* name);

// For the length of a long call: the GIL released, and SIGINT asks palpa's
// loops to stop (they throw, and the error becomes KeyboardInterrupt) instead
// of waiting for Python's handler, which runs only when the call returns.
// Calls from several Python threads at once share the handler: Python's comes
// back when the last of them ends, and a Ctrl-C stops all of them.
class LongCall {
 public:
  LongCall();
  ~LongCall();
  LongCall(const LongCall&) = delete;
  LongCall& operator=(const LongCall&) = delete;

 private:
  py::gil_scoped_release release_;
};

void bind_material(py::module_& m);
void bind_poke(py::module_& m);
void bind_fit(py::module_& m);
void bind_mesh(py::module_& m);
void bind_rest(py::module_& m);
void bind_design(py::module_& m);
void bind_layer(py::module_& m);

}  // namespace palpa::python
