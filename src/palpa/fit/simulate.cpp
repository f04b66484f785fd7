// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/simulate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "palpa/core/error.hpp"

namespace palpa::fit {

Eigen::MatrixXd interpolation_weights(const std::vector<double>& grid, const std::vector<double>& x) {
  const auto n = static_cast<Eigen::Index>(grid.size());
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(x.size()), n);
  if (n == 0) return w;
  if (n == 1) {
    w.col(0).setOnes();
    return w;
  }
  const int order = static_cast<int>(std::min<Eigen::Index>(4, n));  // points per stencil
  for (std::size_t j = 0; j < x.size(); ++j) {
    // Interval k with grid[k] <= x < grid[k+1] (clamped).
    const auto it = std::upper_bound(grid.begin(), grid.end(), x[j]);
    Eigen::Index k = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(it - grid.begin()) - 1, 0, n - 2);
    // Stencil: k−1 … k+2 for cubics, shifted to stay inside the grid.
    Eigen::Index first = std::clamp<Eigen::Index>(k - (order / 2 - 1), 0, n - order);
    for (int a = 0; a < order; ++a) {
      const Eigen::Index ia = first + a;
      double l = 1.0;
      for (int b = 0; b < order; ++b) {
        if (b == a) continue;
        const Eigen::Index ib = first + b;
        l *= (x[j] - grid[static_cast<std::size_t>(ib)]) /
             (grid[static_cast<std::size_t>(ia)] - grid[static_cast<std::size_t>(ib)]);
      }
      w(static_cast<Eigen::Index>(j), ia) = l;
    }
  }
  return w;
}

axisym::PokeSetup poke_setup(const Dataset& d, const MeasuredCurve& c, double layer_depth,
                             const SimulationOptions& o) {
  axisym::PokeSetup s;
  s.mesh_level = o.mesh_level;
  s.extrapolate = o.extrapolate;
  s.element = o.element;
  s.fillet_radius = o.fillet_radius;
  s.contact = d.contact;
  s.geometry.thickness = layer_depth;
  s.geometry.punch_radius = c.radius;
  if (d.test == TestKind::Indentation) {
    double outer = axisym::default_outer_radius(c.radius, layer_depth);
    if (d.lateral_size) outer = std::min(outer, 0.5 * *d.lateral_size);
    s.geometry.outer_radius = outer;
  } else if (d.test == TestKind::Compression) {
    s.test = axisym::PokeTest::Compression;
    s.fillet_radius = 0.0;
    s.geometry.outer_radius = 0.0;
  } else {
    throw Error(ErrorKind::Internal, fmt::format("no axisymmetric set-up for a {} test", to_string(d.test)));
  }
  return s;
}

namespace {

class PokeCurveSimulator final : public CurveSimulator {
 public:
  PokeCurveSimulator(axisym::PokeSetup setup, const MeasuredCurve& c, int steps, const material::Material* reference)
      : setup_(std::move(setup)), x_(c.x), steps_(steps), reference_(reference ? reference->clone() : nullptr) {
    grid_.resize(static_cast<std::size_t>(steps_) + 1);
    for (int k = 0; k <= steps_; ++k) grid_[static_cast<std::size_t>(k)] = c.x.back() * k / steps_;
    weights_ = interpolation_weights(grid_, x_);
  }

  CurvePrediction predict(const material::Material& m, bool sensitivities) override {
    if (!sim_ || sim_->model().material().model() != m.model() ||
        sim_->model().num_params() != m.num_params()) {
      const bool use_reference =
          reference_ && reference_->model() == m.model() && reference_->num_params() == m.num_params();
      axisym::WarmStart warm = sim_ ? sim_->warm_start() : std::move(pending_warm_);
      pending_warm_ = {};
      sim_ = std::make_unique<axisym::PokeSimulator>(use_reference ? *reference_ : m, setup_);
      sim_->set_warm_start(std::move(warm));  // same mesh: still good guesses
    }
    sim_->set_material_params(m.params());
    axisym::PokeOptions po;
    po.max_depth = grid_.back();
    po.steps = steps_;
    po.sensitivities = sensitivities;
    // The fit's materials change little from one evaluation to the next.
    po.warm_start = true;
    if (allow_partial_) {
      // Showing a curve: where the simulation cannot go on (very deep pokes
      // with a small punch), say so soon rather than after ten halvings of
      // 100 Newton iterations each.
      po.max_step_cuts = 8;
      po.newton.max_iterations = 40;
      // Once the rim cells keep under 5% of their volume, a failed depth
      // ends the curve (with that reason) instead of eight halvings of 40
      // iterations each.
      po.give_up_below_jacobian = 0.05;
    }
    CurvePrediction p;
    std::vector<axisym::PokeSample> reached{axisym::PokeSample{}};
    const axisym::PokeSimulator::DepthCallback on_depth = [&](const axisym::PokeModel& model,
                                                              const Eigen::VectorXd& x,
                                                              const axisym::PokeSample& s) {
      if (allow_partial_) reached.push_back(s);
      if (!record_stretches_ || s.depth < grid_.back()) return;
      {
        const auto states = model.element_states(x);
        const axisym::AxisymMesh& mesh = model.mesh();
        for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
          // Ring volume of the rest cell: 2π r_centroid × area (shoelace).
          double area = 0.0, rc = 0.0;
          for (int k = 0; k < 4; ++k) {
            const auto a = mesh.nodes.row(mesh.quads(e, k));
            const auto b = mesh.nodes.row(mesh.quads(e, (k + 1) % 4));
            area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
            rc += 0.25 * a[0];
          }
          const Eigen::Vector3d l = states[static_cast<std::size_t>(e)].stretches;
          const double psi = l.minCoeff() > 0.0 ? m.psi(l) : 0.0;
          p.stretches.push_back({l, psi * 2.0 * 3.14159265358979323846 * rc * std::abs(area)});
        }
      }
    };
    axisym::PokeCurve curve;
    try {
      curve = sim_->run(po, on_depth);
    } catch (const Error& e) {
      if (!allow_partial_ || e.kind() != ErrorKind::Solver) throw;
      return partial(reached, e.problem());
    }
    const auto ng = static_cast<Eigen::Index>(curve.samples.size());
    Eigen::VectorXd f(ng);
    Eigen::MatrixXd df(ng, sensitivities ? m.num_params() : 0);
    for (Eigen::Index k = 0; k < ng; ++k) {
      const auto& s = curve.samples[static_cast<std::size_t>(k)];
      f[k] = s.force;
      if (sensitivities) df.row(k) = s.dforce_dparams.transpose();
      p.grid_x.push_back(s.depth);
      p.grid_y.push_back(s.force);
    }
    const Eigen::VectorXd y = weights_ * f;
    p.y.assign(y.data(), y.data() + y.size());
    if (sensitivities) p.dy_dparams = weights_ * df;
    p.newton_iterations = curve.newton_iterations;
    p.factorizations = curve.factorizations;
    p.reached = grid_.back();
    return p;
  }

 private:
  axisym::PokeSetup setup_;
  std::vector<double> x_;
  int steps_;
  std::vector<double> grid_;
  Eigen::MatrixXd weights_;
  std::unique_ptr<material::Material> reference_;  // fixes penalty and stabilization (may be null)
  std::unique_ptr<axisym::PokeSimulator> sim_;
  axisym::WarmStart pending_warm_;  // set before the first predict()

 public:
  axisym::WarmStart warm_start() const override { return sim_ ? sim_->warm_start() : pending_warm_; }
  void set_warm_start(axisym::WarmStart w) override {
    if (sim_) {
      sim_->set_warm_start(std::move(w));
    } else {
      pending_warm_ = std::move(w);
    }
  }

 private:

  // The prediction from the depths reached before a failure: interpolated on
  // the reached part of the schedule, NaN beyond it.
  CurvePrediction partial(const std::vector<axisym::PokeSample>& reached, const std::string& why) const {
    CurvePrediction p;
    p.failure = why;
    for (const auto& s : reached) {
      p.grid_x.push_back(s.depth);
      p.grid_y.push_back(s.force);
    }
    p.reached = p.grid_x.back();
    std::vector<double> inside;
    for (double x : x_) {
      if (x <= p.reached) inside.push_back(x);
    }
    const Eigen::MatrixXd w = interpolation_weights(p.grid_x, inside);
    const Eigen::VectorXd f = Eigen::Map<const Eigen::VectorXd>(p.grid_y.data(), static_cast<Eigen::Index>(p.grid_y.size()));
    const Eigen::VectorXd y = w * f;
    p.y.assign(x_.size(), std::numeric_limits<double>::quiet_NaN());
    for (Eigen::Index j = 0; j < y.size(); ++j) p.y[static_cast<std::size_t>(j)] = y[j];
    return p;
  }
};

// Homogeneous stress–stretch curves: closed form up to the lateral
// equilibrium (material/homogeneous.hpp), no FEM.
class HomogeneousCurveSimulator final : public CurveSimulator {
 public:
  explicit HomogeneousCurveSimulator(const MeasuredCurve& c) : c_(&c) {}

  CurvePrediction predict(const material::Material& m, bool sensitivities) override {
    const material::CurveSensitivity s = material::homogeneous_curve_sensitivity(m, c_->load_case, c_->x);
    CurvePrediction p;
    for (std::size_t j = 0; j < s.points.size(); ++j) {
      const material::CurvePoint& pt = s.points[j];
      p.y.push_back(pt.nominal);
      if (!record_stretches_) continue;
      const double load = c_->x[j];
      switch (c_->load_case) {
        case material::LoadCase::Uniaxial: p.stretches.push_back({{load, pt.lateral, pt.lateral}, pt.energy}); break;
        case material::LoadCase::Equibiaxial: p.stretches.push_back({{load, load, pt.lateral}, pt.energy}); break;
        case material::LoadCase::SimpleShear: {
          const double r = std::sqrt(1.0 + 0.25 * load * load);
          p.stretches.push_back({{r + 0.5 * std::abs(load), r - 0.5 * std::abs(load), 1.0}, pt.energy});
          break;
        }
      }
    }
    if (sensitivities) p.dy_dparams = s.dnominal_dparams;
    // The curve for plots: 41 loads over the measured range.
    const auto [lo, hi] = std::minmax_element(c_->x.begin(), c_->x.end());
    std::vector<double> loads;
    for (int k = 0; k <= 40; ++k) loads.push_back(*lo + (*hi - *lo) * k / 40.0);
    const material::CurveSensitivity g = material::homogeneous_curve_sensitivity(m, c_->load_case, loads);
    p.grid_x = loads;
    for (const auto& pt : g.points) p.grid_y.push_back(pt.nominal);
    return p;
  }

 private:
  const MeasuredCurve* c_;
};

// Compression between frictionless platens: the sample is in homogeneous
// uniaxial stress (no friction holds its faces, nothing else loads it), so
// the force is exact in closed form, F = π R² |P(λ)| with λ = 1 − travel/H, no
// FEM: no discretization error, and none of the FEM's trouble past ~55%
// compression, where a free lateral surface may wrinkle in theory (Biot's
// critical stretch, ≈ 0.44 for a neo-Hookean) but the measured curves follow
// the homogeneous path.
class FrictionlessCompressionSimulator final : public CurveSimulator {
 public:
  FrictionlessCompressionSimulator(const MeasuredCurve& c, double radius, double height)
      : c_(&c), area_(std::numbers::pi * radius * radius), height_(height) {}

  CurvePrediction predict(const material::Material& m, bool sensitivities) override {
    std::vector<double> stretch;
    for (double x : c_->x) stretch.push_back(1.0 - x / height_);
    if (!(*std::min_element(stretch.begin(), stretch.end()) > 0.0)) {
      throw_input_error(fmt::format("curve {} compresses past the sample's height ({:.4g} mm)", c_->name,
                                    height_ * 1e3),
                        ErrorContext{c_->file.string(), 0, 0, "indentation"}, "platen travel below the height");
    }
    const material::CurveSensitivity s =
        material::homogeneous_curve_sensitivity(m, material::LoadCase::Uniaxial, stretch);
    CurvePrediction p;
    for (std::size_t j = 0; j < s.points.size(); ++j) {
      const material::CurvePoint& pt = s.points[j];
      p.y.push_back(-area_ * pt.nominal);
      if (record_stretches_) p.stretches.push_back({{stretch[j], pt.lateral, pt.lateral}, pt.energy});
    }
    if (sensitivities) p.dy_dparams = -area_ * s.dnominal_dparams;
    const double deepest = *std::max_element(c_->x.begin(), c_->x.end());
    std::vector<double> loads;
    for (int k = 0; k <= 40; ++k) loads.push_back(1.0 - deepest * k / 40.0 / height_);
    const material::CurveSensitivity g =
        material::homogeneous_curve_sensitivity(m, material::LoadCase::Uniaxial, loads);
    for (int k = 0; k <= 40; ++k) {
      p.grid_x.push_back(deepest * k / 40.0);
      p.grid_y.push_back(-area_ * g.points[static_cast<std::size_t>(k)].nominal);
    }
    p.reached = deepest;
    return p;
  }

 private:
  const MeasuredCurve* c_;
  double area_, height_;
};

}  // namespace

std::unique_ptr<CurveSimulator> make_curve_simulator(const Dataset& d, const MeasuredCurve& c,
                                                     double layer_depth, const SimulationOptions& o,
                                                     const material::Material* reference) {
  if (o.steps < 2 || o.steps > 1000) {
    throw_input_error(fmt::format("{} steps", o.steps), ErrorContext{"", 0, 0, "steps"}, "2 to 1000 depth steps");
  }
  switch (d.test) {
    case TestKind::Compression:
      if (d.contact == axisym::PunchContact::Frictionless) {
        return std::make_unique<FrictionlessCompressionSimulator>(c, d.sample_radius, layer_depth);
      }
      return std::make_unique<PokeCurveSimulator>(poke_setup(d, c, layer_depth, o), c, o.steps, reference);
    case TestKind::Indentation:
      return std::make_unique<PokeCurveSimulator>(poke_setup(d, c, layer_depth, o), c, o.steps, reference);
    case TestKind::Homogeneous:
      return std::make_unique<HomogeneousCurveSimulator>(c);
  }
  throw Error(ErrorKind::Internal, fmt::format("no simulator for a {} test", to_string(d.test)));
}

}  // namespace palpa::fit
