// SPDX-License-Identifier: AGPL-3.0-or-later
#include "synthetic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace palpa::test {

namespace {

double smoothstep(double u) { return 0.5 - 0.5 * std::cos(std::numbers::pi * std::clamp(u, 0.0, 1.0)); }

double table_interpolate(const std::vector<double>& x, const std::vector<double>& y, double v) {
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (v <= x[i] || i + 1 == x.size()) {
      const double w = (v - x[i - 1]) / (x[i] - x[i - 1]);
      return (1.0 - w) * y[i - 1] + w * y[i];
    }
  }
  return y.back();
}

}  // namespace

double SyntheticPoke::poke(double t) const {
  if (t < rest_before + ramp_in) return depth * smoothstep((t - rest_before) / ramp_in);
  return depth * (1.0 - smoothstep((t - rest_before - ramp_in) / ramp_out));
}

double SyntheticPoke::expected_force(double x) const {
  auto f = [&](double d) { return stiffness * d + hardening * d * d; };
  return f(preload + x) - f(preload);
}

std::vector<double> calibration_volts() {
  std::vector<double> v;
  for (int i = 0; i <= 20; ++i) v.push_back(0.5 * i);
  return v;
}

std::vector<double> calibration_metres() {
  std::vector<double> d;
  for (double v : calibration_volts()) d.push_back(30e-3 + 8e-3 * v + 0.3e-3 * v * v);
  return d;
}

double interface_depth(const SyntheticPoke& p, double rest_depth, double share, double t) {
  return rest_depth - share * p.poke(t);
}

std::string make_interface_picks(const SyntheticPoke& p, double rest_depth, double share, double clock) {
  std::vector<double> times{0.5, 1.0, 1.5, 1.9};
  for (int i = 0; i <= 12; ++i) times.push_back(2.0 + 0.1 * i);
  for (double t : {3.5, 4.0, 4.5}) times.push_back(t);
  std::string out = "# synthetic ultrasound picks\ntime_s,depth_mm\n";
  for (double t : times) out += fmt::format("{:.4f},{:.5f}\n", t + clock, interface_depth(p, rest_depth, share, t) * 1e3);
  return out;
}

SyntheticLogs make_poke_logs(const SyntheticPoke& p) {
  std::mt19937_64 rng(p.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double phase = 0.7;
  auto delta = [&](double t) {
    return p.preload + p.poke(t) + p.tremor * std::sin(2.0 * std::numbers::pi * p.tremor_hz * t + phase);
  };
  SyntheticLogs out;
  out.force_csv = "# synthetic force gauge log\ntime_s,force_N\n";
  const double force_start = -p.force_lead;
  for (double i = 0;; ++i) {
    const double t = force_start + i / p.force_rate;  // true time
    if (t > p.total()) break;
    const double d = delta(t);
    const double f = p.stiffness * d + p.hardening * d * d + p.force_drift * (t + 1.0) + p.force_noise * unit(rng);
    out.force_csv += fmt::format("{:.6f},{:.5f}\n", t + p.force_clock, f);
  }
  const std::vector<double> volts = calibration_volts();
  const std::vector<double> metres = calibration_metres();
  out.laser_csv = "# synthetic laser log\ntime_s,voltage_V\n";
  for (double i = 0;; ++i) {
    const double t = i / p.laser_rate;
    if (t > p.total()) break;
    const double distance = p.laser_rest - (delta(t) - p.preload) + p.laser_drift * t + p.laser_noise * unit(rng);
    out.laser_csv += fmt::format("{:.6f},{:.7f}\n", t + p.laser_clock, table_interpolate(metres, volts, distance));
  }
  out.calibration_csv = "# synthetic laser calibration\nvoltage_V,distance_mm\n";
  for (std::size_t i = 0; i < volts.size(); ++i) out.calibration_csv += fmt::format("{},{:.6f}\n", volts[i], metres[i] * 1e3);
  return out;
}

SurfaceMesh plate(int n, double size) {
  SurfaceMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      m.V.row(j * (n + 1) + i) << size * (static_cast<double>(i) / n - 0.5), size * (static_cast<double>(j) / n - 0.5), 0.0;
    }
  }
  m.F.resize(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  }
  return m;
}

std::string obj_text(const SurfaceMesh& mesh) {
  std::string out = "# synthetic support surface [m]\n";
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    out += fmt::format("v {} {} {}\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    out += fmt::format("f {} {} {}\n", mesh.F(f, 0) + 1, mesh.F(f, 1) + 1, mesh.F(f, 2) + 1);
  }
  return out;
}

std::string pressure_locations_csv(const SyntheticPressure& s) {
  std::string out = "# synthetic sensor locations\nlocation,x_mm,y_mm,z_mm\n";
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const Eigen::Vector3d& p = s.positions[i];
    out += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", i + 1, p.x() * 1e3, p.y() * 1e3, p.z() * 1e3);
  }
  return out;
}

std::string pressure_samples_csv(const SyntheticPressure& s) {
  std::mt19937_64 rng(s.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::string out = "# synthetic pressure-sensor samples (10 Hz)\nlocation,reading_V,reference_V\n";
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const double posture = 1.0 + 0.2 * std::sin(1.7 * static_cast<double>(i));
    const double reading = s.ratio(s.positions[i]) * posture;
    for (std::size_t k = 0; k < s.samples; ++k) {
      const double level = static_cast<double>(k % 10) - 4.5;
      const double rk = 1.0 + s.ripple * level / 4.5 + s.noise * unit(rng);
      const double ek = 1.0 + s.ripple * (static_cast<double>((k + 3) % 10) - 4.5) / 4.5 + s.noise * unit(rng);
      out += fmt::format("{},{:.{}g},{:.{}g}\n", i + 1, reading * rk, s.digits, posture * ek, s.digits);
    }
  }
  return out;
}

}  // namespace palpa::test
