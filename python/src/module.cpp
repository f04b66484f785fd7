// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa._palpa: the compiled part of the Python module.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <memory>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/parallel.hpp"
#include "palpa/core/version.hpp"
#include "palpa/solve/blas.hpp"

namespace palpa::python {

namespace {

std::unique_ptr<tbb::global_control> g_threads;

constexpr int kDimensions = static_cast<int>(Dimension::PressurePerLength) + 1;

Dimension dimension_named(const std::string& name) {
  std::string names;
  for (int k = 0; k < kDimensions; ++k) {
    const auto d = static_cast<Dimension>(k);
    if (dimension_name(d) == name) return d;
    names += fmt::format("{}{}", k ? ", " : "", dimension_name(d));
  }
  throw_input_error(fmt::format("unknown dimension '{}'", name), ErrorContext{"", 0, 0, "dimension"}, names);
}

// The SI value of `text` in whichever dimension its unit has (none: a number).
double any_quantity(const std::string& text) {
  for (int k = 1; k < kDimensions; ++k) {
    try {
      return parse_quantity(text, static_cast<Dimension>(k), ErrorContext{});
    } catch (const Error&) {
    }
  }
  return parse_quantity(text, Dimension::Dimensionless, ErrorContext{"", 0, 0, "text"});
}

}  // namespace

}  // namespace palpa::python

PYBIND11_MODULE(_palpa, m) {
  using namespace palpa;
  using namespace palpa::python;
  m.doc() = "palpa: soft-tissue mechanics (compiled part; import palpa)";
  m.attr("__version__") = std::string(kVersion);
  // As the command line starts: the same threads, the same numbers.
  set_default_blas_threads();

  static py::exception<Error> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<Error> solver_error(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      // A message may quote bytes of a file that are not UTF-8: they are shown
      // as U+FFFD rather than lose the whole message.
      const std::string what = e.what();
      PyObject* text = PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), "replace");
      PyObject* type = PyExc_RuntimeError;
      switch (e.kind()) {
        case ErrorKind::Input: type = input_error.ptr(); break;
        case ErrorKind::Solver: type = solver_error.ptr(); break;
        case ErrorKind::Interrupted: type = PyExc_KeyboardInterrupt; break;
        case ErrorKind::Internal: type = PyExc_RuntimeError; break;
      }
      PyErr_SetObject(type, text);
      Py_XDECREF(text);
    }
  });

  m.def(
      "quantity",
      [](const std::string& text, const std::string& dimension) {
        if (!dimension.empty()) return parse_quantity(text, dimension_named(dimension), ErrorContext{});
        return any_quantity(text);
      },
      py::arg("text"), py::arg("dimension") = "",
      "The SI value of a quantity with its unit: quantity('12 kPa') -> 12000.0. With `dimension` ('length', "
      "'force', 'pressure', ...) a unit of another kind is refused.");
  m.def(
      "set_threads",
      [](int n) {
        if (n < 0 || n > kMaxThreads) {
          throw_input_error(fmt::format("{} threads", n), ErrorContext{"", 0, 0, "n"},
                            fmt::format("0 (all cores) to {}", kMaxThreads));
        }
        g_threads.reset();
        if (n > 0) g_threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, n);
      },
      py::arg("n"), "Threads palpa's own loops may use (0: every core, the default).");
  m.def(
      "threads", [] { return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism); },
      "Threads palpa's own loops may use now.");

  m.def(
      "set_log_level",
      [](const std::string& level) {
        for (const auto l : {spdlog::level::debug, spdlog::level::info, spdlog::level::warn, spdlog::level::err,
                             spdlog::level::off}) {
          const auto name = spdlog::level::to_string_view(l);
          if (level == std::string_view(name.data(), name.size())) return spdlog::set_level(l);
        }
        throw_input_error(fmt::format("unknown log level '{}'", level), ErrorContext{"", 0, 0, "level"},
                          "debug, info, warning, error or off");
      },
      py::arg("level"), "How much palpa logs to stdout: debug, info (the default), warning, error or off.");

  bind_material(m);
  bind_poke(m);
  bind_fit(m);
  bind_mesh(m);
  bind_rest(m);
  bind_design(m);
  bind_layer(m);
}
