// SPDX-License-Identifier: AGPL-3.0-or-later
#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <mutex>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"

namespace palpa::python {

namespace {

py::array checked_numeric(const py::handle& a, const char* name, const char* kinds) {
  py::array arr = py::array::ensure(a);
  if (!arr) throw py::type_error(fmt::format("{}: expected an array of numbers, got {}", name,
                                             std::string(py::str(py::type::of(a).attr("__name__")))));
  const char kind = arr.dtype().kind();
  if (std::string_view(kinds).find(kind) == std::string_view::npos) {
    throw py::type_error(fmt::format("{}: expected {} numbers, got an array of dtype {}", name,
                                     kinds[0] == 'i' ? "integer" : "real", std::string(py::str(arr.dtype()))));
  }
  return arr;
}

ErrorContext field(const char* name) { return ErrorContext{"", 0, 0, name}; }

void check_shape(const py::array& arr, Eigen::Index cols, const char* name, bool allow_empty) {
  const bool ok = cols == 0 ? arr.ndim() == 1 : arr.ndim() == 2 && arr.shape(1) == cols;
  if (!ok) {
    std::string shape;
    for (py::ssize_t k = 0; k < arr.ndim(); ++k) shape += fmt::format("{}{}", k ? ", " : "", arr.shape(k));
    throw_input_error(fmt::format("an array of shape ({})", shape), field(name),
                      cols == 0 ? std::string("a 1-D array") : fmt::format("an array of shape (n, {})", cols));
  }
  if (!allow_empty && arr.shape(0) == 0) throw_input_error("an empty array", field(name), "at least one row");
}

}  // namespace

Eigen::MatrixXd float_matrix(const py::handle& a, Eigen::Index cols, const char* name, bool allow_empty) {
  const py::array arr = checked_numeric(a, name, "fiu");
  check_shape(arr, cols, name, allow_empty);
  // (the constructor raises what the copy raised, a MemoryError of a view too
  // large to copy among them; ensure() would return a null array instead)
  const py::array_t<double, py::array::c_style | py::array::forcecast> c(arr);
  const Eigen::Index rows = c.shape(0);
  const Eigen::Index width = cols == 0 ? 1 : cols;
  Eigen::MatrixXd out(rows, width);
  const double* data = c.data();
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < width; ++j) {
      const double v = data[i * width + j];
      if (!std::isfinite(v)) {
        throw_input_error(fmt::format("{} at row {}", v, i), field(name), "finite numbers");
      }
      out(i, j) = v;
    }
  }
  return out;
}

Eigen::VectorXd float_vector(const py::handle& a, const char* name, bool allow_empty) {
  return float_matrix(a, 0, name, allow_empty).col(0);
}

Eigen::MatrixXi index_matrix(const py::handle& a, Eigen::Index cols, Eigen::Index bound, const char* name) {
  const py::array arr = checked_numeric(a, name, "iu");
  check_shape(arr, cols, name, false);
  const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> c(arr);
  Eigen::MatrixXi out(c.shape(0), cols);
  const std::int64_t* data = c.data();
  for (Eigen::Index i = 0; i < out.rows(); ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      const std::int64_t v = data[i * cols + j];
      if (v < 0 || v >= bound) {
        throw_input_error(fmt::format("index {} at row {}", v, i), field(name),
                          fmt::format("indices from 0 to {}", bound - 1));
      }
      out(i, j) = static_cast<int>(v);
    }
  }
  return out;
}

py::array_t<double> to_numpy(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  }
  return out;
}

py::array_t<double> to_numpy(const Eigen::VectorXd& v) {
  py::array_t<double> out(v.size());
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  return out;
}

py::array_t<std::int64_t> to_numpy(const Eigen::MatrixXi& m) {
  py::array_t<std::int64_t> out({m.rows(), m.cols()});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  }
  return out;
}

double quantity_arg(const py::handle& value, Dimension d, const char* name) {
  if (py::isinstance<py::bool_>(value)) {
    throw py::type_error(fmt::format("{}: expected a number or a string with a unit, got a bool", name));
  }
  if (py::isinstance<py::str>(value)) return parse_quantity(value.cast<std::string>(), d, field(name));
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value) ||
      py::hasattr(value, "__float__")) {
    const double v = py::float_(py::reinterpret_borrow<py::object>(value));
    if (!std::isfinite(v)) throw_input_error(fmt::format("{}", v), field(name), "a finite number");
    return v;
  }
  throw py::type_error(fmt::format("{}: expected a number (SI) or a string with a unit such as '{}', got {}", name,
                                   dimension_example(d),
                                   std::string(py::str(py::type::of(value).attr("__name__")))));
}

namespace {

void on_sigint(int) { request_interrupt(); }

// Long calls running now (from any Python threads): the first one in installs
// the handler, the last one out restores Python's.
std::mutex g_calls_mutex;
int g_calls = 0;
struct sigaction g_python_handler {};
bool g_installed = false;

}  // namespace

LongCall::LongCall() {
  std::lock_guard lock(g_calls_mutex);
  if (g_calls++ > 0) return;
  clear_interrupt();
  struct sigaction action {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  g_installed = sigaction(SIGINT, &action, &g_python_handler) == 0;
}

LongCall::~LongCall() {
  std::lock_guard lock(g_calls_mutex);
  if (--g_calls > 0) return;
  if (g_installed) sigaction(SIGINT, &g_python_handler, nullptr);
  g_installed = false;
  // A Ctrl-C that came after the last check: Python's handler gets it now.
  // (One that stopped the call comes back as the call's KeyboardInterrupt.)
  if (interrupt_requested() && std::uncaught_exceptions() == 0) PyErr_SetInterrupt();
  clear_interrupt();
}

}  // namespace palpa::python
