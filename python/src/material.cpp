// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa.Material: the models of the registry, their files, energies, stresses
// and homogeneous curves.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "common.hpp"
#include "palpa/core/error.hpp"
#include "palpa/material/homogeneous.hpp"
#include "palpa/material/material_file.hpp"
#include "palpa/material/registry.hpp"

namespace palpa::python {

namespace {

using material::Material;
using MaterialPtr = std::shared_ptr<Material>;

// The keyword arguments of Material(model, ...) as named parameter values.
material::ParameterValues values_from(const material::ModelSpec& model, const py::kwargs& kwargs) {
  material::ParameterValues v;
  for (const auto& [key_handle, value] : kwargs) {
    const std::string key = py::str(key_handle);
    const material::ParameterSpec* spec = model.find_any(key);
    if (spec == nullptr) {
      v.scalars[key] = 0.0;  // refused by make_material, naming the model's parameters
      continue;
    }
    switch (spec->kind) {
      case material::ParameterKind::Scalar: v.scalars[key] = quantity_arg(value, spec->dimension, key.c_str()); break;
      case material::ParameterKind::List: {
        if (py::isinstance<py::str>(value)) throw py::type_error(fmt::format("{}: expected a list, got a string", key));
        std::vector<double> list;
        for (const py::handle item : py::iter(value)) list.push_back(quantity_arg(item, spec->dimension, key.c_str()));
        v.lists[key] = std::move(list);
        break;
      }
      case material::ParameterKind::Spline: {
        if (!py::isinstance<py::dict>(value)) {
          throw py::type_error(fmt::format("{}: expected a dict with 'knots' and 'values' (Pa)", key));
        }
        const py::dict d = py::reinterpret_borrow<py::dict>(value);
        for (const auto& [k, unused] : d) {
          const std::string name = py::str(k);
          if (name != "knots" && name != "values") {
            throw_input_error(fmt::format("'{}' in spline {}", name, key), ErrorContext{"", 0, 0, key},
                              "'knots' and 'values'");
          }
        }
        if (!d.contains("knots") || !d.contains("values")) {
          throw_input_error(fmt::format("spline {} without knots or values", key), ErrorContext{"", 0, 0, key},
                            "'knots' and 'values'");
        }
        const Eigen::VectorXd knots = float_vector(d["knots"], (key + ".knots").c_str());
        const Eigen::VectorXd values = float_vector(d["values"], (key + ".values").c_str());
        v.splines[key] = material::SplineValues{{knots.data(), knots.data() + knots.size()},
                                                {values.data(), values.data() + values.size()}};
        break;
      }
    }
  }
  return v;
}

py::dict parameters_of(const Material& m) {
  const material::ParameterValues v = material::parameter_values(m);
  py::dict out;
  for (const auto& [k, x] : v.scalars) out[py::str(k)] = x;
  for (const auto& [k, x] : v.lists) {
    out[py::str(k)] = to_numpy(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(x.data(), std::ssize(x))));
  }
  for (const auto& [k, s] : v.splines) {
    py::dict d;
    d["knots"] = to_numpy(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(s.knots.data(), std::ssize(s.knots))));
    d["values"] = to_numpy(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(s.values.data(), std::ssize(s.values))));
    out[py::str(k)] = d;
  }
  return out;
}

material::LoadCase load_case(const std::string& test) { return material::parse_load_case(test); }

}  // namespace

void bind_material(py::module_& m) {
  py::class_<Material, MaterialPtr> cls(m, "Material", R"doc(
A hyperelastic material: a model of palpa.models() and its parameters.

    palpa.Material("neo-hookean", E="12 kPa", nu=0.45)
    palpa.Material("ogden", mu=["6 kPa", "-0.5 kPa"], alpha=[4.7, -2], nu=0.45)
    palpa.Material.load("material.json")

Parameters are spelled as in material files; each takes a float in SI units
(Pa for moduli, 1/Pa for D1) or a string with its unit ("12 kPa").
)doc");
  cls.def(py::init([](const std::string& model, const py::kwargs& kwargs) {
            const material::ModelSpec& spec = material::model_spec(model, ErrorContext{"", 0, 0, "model"});
            return MaterialPtr(material::make_material(spec, values_from(spec, kwargs), ErrorContext{}));
          }),
          py::arg("model"))
      .def_static(
          "load", [](const std::filesystem::path& path) { return MaterialPtr(material::read_material_file(path).material); },
          py::arg("path"), "Reads a material file (material.json).")
      .def(
          "save",
          [](const Material& self, const std::filesystem::path& path, const std::string& method) {
            material::write_material_file(path, self, material::make_provenance(method));
          },
          py::arg("path"), py::arg("method") = "palpa Python (user-specified parameters)",
          "Writes a material file atomically; `method` goes into its provenance.")
      .def_property_readonly("model", [](const Material& self) { return std::string(self.model()); })
      .def_property_readonly("description", &Material::description)
      .def_property_readonly("parameters", &parameters_of,
                             "The parameters by name, SI (moduli in Pa); Ogden's as arrays, a spline's as dicts "
                             "of knots and values (Pa).")
      .def(
          "to_json",
          [](const Material& self) { return material::material_to_json(self).dump(); },
          "The material as the JSON text of a material file (without provenance).")
      .def(
          "small_strain",
          [](const Material& self) {
            const material::ElasticConstants c = material::small_strain_constants(self);
            py::dict d;
            d["E"] = c.young();
            d["nu"] = c.poisson();
            d["shear_modulus"] = c.mu;
            d["bulk_modulus"] = c.bulk();
            return d;
          },
          "Small-strain constants: E, nu, shear and bulk modulus (Pa).")
      .def(
          "energy",
          [](const Material& self, const py::handle& stretches) {
            const Eigen::MatrixXd l = float_matrix(stretches, 3, "stretches");
            Eigen::VectorXd out(l.rows());
            for (Eigen::Index i = 0; i < l.rows(); ++i) out[i] = self.psi(l.row(i).transpose());
            return to_numpy(out);
          },
          py::arg("stretches"), "Energy density Ψ (Pa = J/m³) at each row of principal stretches, an (n, 3) array.")
      .def(
          "stress",
          [](const Material& self, const py::handle& stretches) {
            const Eigen::MatrixXd l = float_matrix(stretches, 3, "stretches");
            Eigen::MatrixXd out(l.rows(), 3);
            for (Eigen::Index i = 0; i < l.rows(); ++i) out.row(i) = self.dpsi_dlambda(l.row(i).transpose()).transpose();
            return to_numpy(out);
          },
          py::arg("stretches"),
          "Principal nominal stresses ∂Ψ/∂λ (Pa) at each row of principal stretches, an (n, 3) array.")
      .def(
          "curve",
          [](const Material& self, const std::string& test, const py::handle& loads) {
            const material::LoadCase lc = load_case(test);
            const Eigen::VectorXd x = float_vector(loads, "loads");
            const std::span<const double> span(x.data(), static_cast<std::size_t>(x.size()));
            const material::CurveSensitivity c = material::homogeneous_curve_sensitivity(self, lc, span);
            Eigen::VectorXd lateral(x.size()), nominal(x.size()), cauchy(x.size()), energy(x.size());
            for (Eigen::Index i = 0; i < x.size(); ++i) {
              const material::CurvePoint& p = c.points[static_cast<std::size_t>(i)];
              lateral[i] = p.lateral;
              nominal[i] = p.nominal;
              cauchy[i] = p.cauchy;
              energy[i] = p.energy;
            }
            py::dict d;
            d["load"] = to_numpy(x);
            d["lateral"] = to_numpy(lateral);
            d["nominal"] = to_numpy(nominal);
            d["cauchy"] = to_numpy(cauchy);
            d["energy"] = to_numpy(energy);
            return d;
          },
          py::arg("test"), py::arg("loads"),
          "Homogeneous test with traction-free lateral faces: test 'uniaxial', 'equibiaxial' (loads: stretches) "
          "or 'shear' (loads: shear strains). Returns arrays load, lateral (stretch), nominal and cauchy "
          "stress (Pa), energy (Pa).")
      .def("__repr__", [](const Material& self) {
        return fmt::format("palpa.Material({})", material::material_to_json(self)["parameters"].dump());
      });

  m.def(
      "models",
      [] {
        py::dict out;
        for (const material::ModelSpec& s : material::models()) {
          py::dict d;
          d["summary"] = std::string(s.summary);
          d["parameters"] = s.parameter_summary();
          d["fittable"] = s.fittable;
          out[py::str(std::string(s.name))] = d;
        }
        return out;
      },
      "The material models: name -> summary, parameters, whether palpa.fit can fit it.");
}

}  // namespace palpa::python
