// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa.poke: a punch pressed into a layer (or a sample compressed between
// plates), the axisymmetric simulation of `palpa poke`.

#include <fmt/format.h>

#include <chrono>
#include <pybind11/stl.h>

#include "common.hpp"
#include "palpa/axisym/element.hpp"
#include "palpa/axisym/output.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/core/error.hpp"

namespace palpa::python {

namespace {

struct PokeResult {
  Eigen::VectorXd indentation, force, iterations, substeps, residual, penetration, min_det_f, contact_nodes,
      mesh_correction;
  Eigen::MatrixXd sensitivities;  // (n_depths, n_params), empty without
  std::vector<std::string> parameter_names;
  int newton_iterations = 0;
  std::vector<UnstructuredGrid> grids;  // the deformed mesh per depth, when asked
};

// A deformed mesh as arrays: points (P, 3) as (r, z, 0) [m], quads (C, 4) and
// every point and cell field of palpa poke's VTU frames by name (SI).
py::dict grid_dict(const UnstructuredGrid& g) {
  py::dict d;
  d["points"] = to_numpy(Eigen::MatrixXd(g.points));
  for (const CellBlock& b : g.cells) d["quads"] = to_numpy(b.nodes);
  for (const auto* fields : {&g.point_data, &g.cell_data}) {
    for (const DataArray& a : *fields) {
      d[py::str(a.name)] = a.values.cols() == 1 ? py::object(to_numpy(Eigen::VectorXd(a.values.col(0))))
                                                : py::object(to_numpy(a.values));
    }
  }
  return d;
}

PokeResult run_poke(const material::Material& material, double thickness, double radius, double depth, int steps,
                    const std::string& test, const std::string& contact, int mesh_level, bool extrapolate,
                    const std::string& element, double fillet, double outer_radius, bool sensitivities, bool fields) {
  axisym::PokeSetup setup;
  setup.test = axisym::parse_poke_test(test);
  if (setup.test == axisym::PokeTest::Indentation) {
    setup.contact = axisym::parse_punch_contact(contact.empty() ? "stick" : contact);
  } else {
    setup.contact = axisym::parse_platen_contact(contact.empty() ? "bonded" : contact);
  }
  setup.geometry.punch_radius = radius;
  setup.geometry.thickness = thickness;
  setup.geometry.outer_radius = outer_radius;
  setup.mesh_level = mesh_level;
  setup.extrapolate = extrapolate;
  setup.element = axisym::parse_element_formulation(element);
  setup.fillet_radius = fillet;
  axisym::PokeOptions options;
  options.max_depth = depth;
  options.steps = steps;
  options.sensitivities = sensitivities;
  PokeResult r;
  axisym::PokeCurve curve;
  {
    LongCall call;
    axisym::PokeSimulator sim(material, setup);
    axisym::PokeSimulator::DepthCallback on_depth;
    if (fields) {
      on_depth = [&r](const axisym::PokeModel& model, const Eigen::VectorXd& x, const axisym::PokeSample&) {
        r.grids.push_back(axisym::deformed_grid(model, x));
      };
    }
    curve = sim.run(options, on_depth);
  }
  const auto n = static_cast<Eigen::Index>(curve.samples.size());
  for (Eigen::VectorXd* v : {&r.indentation, &r.force, &r.iterations, &r.substeps, &r.residual, &r.penetration,
                             &r.min_det_f, &r.contact_nodes, &r.mesh_correction}) {
    v->resize(n);
  }
  if (sensitivities) r.sensitivities.resize(n, material.num_params());
  for (Eigen::Index i = 0; i < n; ++i) {
    const axisym::PokeSample& s = curve.samples[static_cast<std::size_t>(i)];
    r.indentation[i] = s.depth;
    r.force[i] = s.force;
    r.iterations[i] = s.newton_iterations;
    r.substeps[i] = s.substeps;
    r.residual[i] = s.residual;
    r.penetration[i] = s.max_penetration;
    r.min_det_f[i] = s.min_jacobian;
    r.contact_nodes[i] = s.contact_nodes;
    r.mesh_correction[i] = s.mesh_correction;
    if (sensitivities) r.sensitivities.row(i) = s.dforce_dparams.transpose();
  }
  for (Eigen::Index k = 0; k < material.num_params(); ++k) r.parameter_names.push_back(material.param_info(k).name);
  r.newton_iterations = curve.newton_iterations;
  return r;
}

// Wall times [s] of the C++ part alone of `repeats` pokes (simulator built,
// curve run; one mesh, no extrapolation), for the call-overhead benchmark.
std::vector<double> cpp_seconds(const material::Material& material, double thickness, double radius, double depth,
                                int steps, int mesh_level, int repeats) {
  axisym::PokeSetup setup;
  setup.geometry.punch_radius = radius;
  setup.geometry.thickness = thickness;
  setup.mesh_level = mesh_level;
  setup.extrapolate = false;
  axisym::PokeOptions options;
  options.max_depth = depth;
  options.steps = steps;
  std::vector<double> out;
  py::gil_scoped_release release;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    axisym::PokeSimulator sim(material, setup);
    const axisym::PokeCurve curve = sim.run(options);
    out.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return out;
}

}  // namespace

void bind_poke(py::module_& m) {
  m.def("_poke_cpp_seconds", &cpp_seconds, py::arg("material"), py::arg("thickness"), py::arg("radius"),
        py::arg("depth"), py::arg("steps"), py::arg("mesh_level"), py::arg("repeats"),
        "Wall times of the C++ part alone of `repeats` pokes (lengths in m), for benchmarks.");
  py::class_<PokeResult>(m, "PokeResult", "The curve of palpa.poke, one entry per depth (depth 0 first).")
      .def_property_readonly("indentation", [](const PokeResult& r) { return to_numpy(r.indentation); },
                             "Indentation (compression: plate travel) [m].")
      .def_property_readonly("force", [](const PokeResult& r) { return to_numpy(r.force); }, "Force [N].")
      .def_property_readonly("iterations", [](const PokeResult& r) { return to_numpy(r.iterations); },
                             "Newton iterations to reach each depth.")
      .def_property_readonly("substeps", [](const PokeResult& r) { return to_numpy(r.substeps); },
                             "Sub-steps each depth increment needed (1 unless it was cut).")
      .def_property_readonly("residual", [](const PokeResult& r) { return to_numpy(r.residual); },
                             "Final force residual ‖g‖∞ [N].")
      .def_property_readonly("penetration", [](const PokeResult& r) { return to_numpy(r.penetration); },
                             "Largest penetration of the punch into the layer [m].")
      .def_property_readonly("min_det_f", [](const PokeResult& r) { return to_numpy(r.min_det_f); },
                             "Smallest det F over the mesh.")
      .def_property_readonly("contact_nodes", [](const PokeResult& r) { return to_numpy(r.contact_nodes); },
                             "Surface nodes on the punch.")
      .def_property_readonly("mesh_correction", [](const PokeResult& r) { return to_numpy(r.mesh_correction); },
                             "With extrapolation: the force's estimated discretization error [N]; 0 without.")
      .def_property_readonly(
          "sensitivities",
          [](const PokeResult& r) -> py::object {
            if (r.sensitivities.size() == 0) return py::none();
            return to_numpy(r.sensitivities);
          },
          "dF/dθ per depth and material parameter, (n_depths, n_params) [N per SI unit], or None.")
      .def_readonly("parameter_names", &PokeResult::parameter_names, "The columns of `sensitivities`.")
      .def_property_readonly(
          "fields",
          [](const PokeResult& r) -> py::object {
            if (r.grids.empty()) return py::none();
            py::list out;
            for (const UnstructuredGrid& g : r.grids) out.append(grid_dict(g));
            return out;
          },
          "With fields=True: per converged depth a dict of the deformed mesh: points (P, 3) as (r, z, 0) [m], "
          "quads (C, 4), point fields (displacement_m, pressure_Pa, ...) and cell fields (det_F, "
          "principal_stretches, von_mises_stress_Pa, ...); else None.")
      .def_readonly("newton_iterations", &PokeResult::newton_iterations, "Newton iterations in all.");

  m.def(
      "poke",
      [](const std::shared_ptr<material::Material>& material, const py::handle& thickness, const py::handle& radius,
         const py::handle& depth, int steps, const std::string& test, const std::string& contact, int mesh_level,
         bool extrapolate, const std::string& element, const py::handle& fillet, const py::handle& outer_radius,
         bool sensitivities, bool fields) {
        if (!material) throw py::type_error("material: expected a palpa.Material, got None");
        const auto positive = [](const py::handle& v, const char* name) {
          const double x = quantity_arg(v, Dimension::Length, name);
          if (!(x > 0.0)) throw_input_error(format_quantity(x, Dimension::Length), ErrorContext{"", 0, 0, name},
                                            "a positive length");
          return x;
        };
        if (steps < 1) throw_input_error(fmt::format("{} steps", steps), ErrorContext{"", 0, 0, "steps"}, "1 or more");
        return run_poke(*material, positive(thickness, "thickness"), positive(radius, "radius"),
                        positive(depth, "depth"), steps, test, contact, mesh_level, extrapolate,
                        element, quantity_arg(fillet, Dimension::Length, "fillet"),
                        quantity_arg(outer_radius, Dimension::Length, "outer_radius"), sensitivities, fields);
      },
      py::arg("material"), py::kw_only(), py::arg("thickness"), py::arg("radius"), py::arg("depth"),
      py::arg("steps") = 20, py::arg("test") = "indentation", py::arg("contact") = "", py::arg("mesh_level") = 2,
      py::arg("extrapolate") = true, py::arg("element") = "fbar", py::arg("fillet") = 0.0,
      py::arg("outer_radius") = 0.0, py::arg("sensitivities") = false, py::arg("fields") = false,
      R"doc(Presses a rigid flat cylindrical punch of `radius` into a layer of `thickness` on a
rigid base, to `depth` in `steps` equal increments (test='compression': a cylindrical
sample of radius `radius` and height `thickness` between two plates). Lengths in metres
or as strings with units ("3 mm"). contact: 'stick' (default) or 'frictionless' for a
punch, 'bonded' (default) or 'frictionless' for plates. sensitivities=True: dF/dθ per
depth; fields=True: the deformed mesh and its fields per depth. Releases the GIL; Ctrl-C
raises KeyboardInterrupt. Returns a PokeResult.)doc");
}

}  // namespace palpa::python
