// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/report/pressure_template.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "palpa/core/atomic_file.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/pearson.hpp"
#include "palpa/io/grid.hpp"
#include "palpa/report/colormap.hpp"
#include "palpa/report/svg_text.hpp"

namespace palpa::report {
namespace {

constexpr int kSub = 4;  // samples per pixel side

// A footprint's centroid, its principal axes (columns: major, minor) and the
// spread along each (√ of the area's second moment about the centroid).
struct Frame2 {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Matrix2d axes = Eigen::Matrix2d::Identity();
  Eigen::Vector2d spread = Eigen::Vector2d::Ones();
};

// From area-weighted points.
Frame2 principal_frame(const std::vector<Eigen::Vector2d>& points,
                       const std::vector<double>& weights) {
  double w = 0.0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    w += weights[i];
    c += weights[i] * points[i];
  }
  c /= w;
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i)
    m += weights[i] * (points[i] - c) * (points[i] - c).transpose();
  m /= w;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(m);
  Frame2 f;
  f.centre = c;
  f.axes.col(0) = eig.eigenvectors().col(1);  // largest eigenvalue: the major axis
  f.axes.col(1) = eig.eigenvectors().col(0);
  f.spread = Eigen::Vector2d(std::sqrt(std::max(eig.eigenvalues()[1], 0.0)),
                             std::sqrt(std::max(eig.eigenvalues()[0], 0.0)));
  return f;
}

// A triangle of the skin seen in the plate's plane, with its corner pressures.
struct FlatTriangle {
  Eigen::Vector2d a, b, c;
  Eigen::Vector3d p;
};

// The simulated pressure at plane points: linear over the triangle that holds
// the point, the largest over overlapping triangles, 0 off them. Triangles
// are binned on a uniform grid over their bounding box.
class FlatSampler {
 public:
  explicit FlatSampler(std::vector<FlatTriangle> triangles) : triangles_(std::move(triangles)) {
    lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo_;
    for (const FlatTriangle& t : triangles_) {
      for (const Eigen::Vector2d* p : {&t.a, &t.b, &t.c}) {
        lo_ = lo_.cwiseMin(*p);
        hi = hi.cwiseMax(*p);
      }
    }
    n_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(triangles_.size()))));
    cell_ = ((hi - lo_) / n_).cwiseMax(Eigen::Vector2d::Constant(1e-12));
    bins_.assign(static_cast<std::size_t>(n_ * n_), {});
    for (std::size_t k = 0; k < triangles_.size(); ++k) {
      const FlatTriangle& t = triangles_[k];
      const Eigen::Vector2d a = t.a.cwiseMin(t.b).cwiseMin(t.c),
                            b = t.a.cwiseMax(t.b).cwiseMax(t.c);
      const int i0 = bin(a.x(), 0), i1 = bin(b.x(), 0), j0 = bin(a.y(), 1), j1 = bin(b.y(), 1);
      for (int i = i0; i <= i1; ++i) {
        for (int j = j0; j <= j1; ++j)
          bins_[static_cast<std::size_t>(i * n_ + j)].push_back(static_cast<int>(k));
      }
    }
  }

  double operator()(const Eigen::Vector2d& q) const {
    if ((q.array() < lo_.array()).any() || (q.array() > (lo_ + n_ * cell_).array()).any())
      return 0.0;
    double best = 0.0;
    for (const int k : bins_[static_cast<std::size_t>(bin(q.x(), 0) * n_ + bin(q.y(), 1))]) {
      const FlatTriangle& t = triangles_[static_cast<std::size_t>(k)];
      const Eigen::Vector2d e1 = t.b - t.a, e2 = t.c - t.a, d = q - t.a;
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      if (det == 0.0) continue;
      const double s = (d.x() * e2.y() - d.y() * e2.x()) / det;
      const double u = (e1.x() * d.y() - e1.y() * d.x()) / det;
      if (s < -1e-12 || u < -1e-12 || s + u > 1.0 + 1e-12) continue;
      best = std::max(best, (1.0 - s - u) * t.p[0] + s * t.p[1] + u * t.p[2]);
    }
    return best;
  }

 private:
  int bin(double x, int axis) const {
    return std::clamp(static_cast<int>((x - lo_[axis]) / cell_[axis]), 0, n_ - 1);
  }

  std::vector<FlatTriangle> triangles_;
  Eigen::Vector2d lo_, cell_;
  int n_ = 1;
  std::vector<std::vector<int>> bins_;
};

}  // namespace

PressureGrid read_pressure_grid(const std::filesystem::path& path, double pixel, double to_pa) {
  if (!(pixel > 0.0) || !(to_pa > 0.0)) {
    throw Error(ErrorKind::Input,
                fmt::format("{}: a pixel of {} m in units of {} Pa", path.string(), pixel, to_pa),
                {}, "a pixel size and a unit > 0");
  }
  PressureGrid g;
  g.pixel = pixel;
  g.pressure = read_number_grid(path) * to_pa;
  for (Eigen::Index r = 0; r < g.pressure.rows(); ++r) {
    for (Eigen::Index c = 0; c < g.pressure.cols(); ++c) {
      if (g.pressure(r, c) < 0.0) {
        throw Error(ErrorKind::Input,
                    fmt::format("a negative pressure {:g} in row {}, field {}",
                                g.pressure(r, c) / to_pa, r + 1, c + 1),
                    ErrorContext{path.string(), 0, 0, {}}, "pressures ≥ 0");
      }
    }
  }
  if (!(g.pressure.maxCoeff() > 0.0)) {
    throw Error(ErrorKind::Input, "no pressure anywhere in the grid",
                ErrorContext{path.string(), 0, 0, {}}, "a pressure map");
  }
  return g;
}

TemplateComparison compare_with_template(const SurfaceMesh& skin, const Eigen::VectorXd& pressure,
                                         const Eigen::Vector3d& normal,
                                         const PressureGrid& reference) {
  // The plate's plane: e1, e2 ⟂ normal, right-handed seen from the body.
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d a =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = (a - a.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  std::vector<FlatTriangle> triangles;
  std::vector<Eigen::Vector2d> sim_points;
  std::vector<double> sim_weights;
  for (Eigen::Index f = 0; f < skin.F.rows(); ++f) {
    const Eigen::Vector3d p(pressure[skin.F(f, 0)], pressure[skin.F(f, 1)], pressure[skin.F(f, 2)]);
    if (!(p.maxCoeff() > 0.0)) continue;
    FlatTriangle t;
    const auto flat = [&](int k) {
      const Eigen::Vector3d x = skin.V.row(skin.F(f, k)).transpose();
      return Eigen::Vector2d(x.dot(e1), x.dot(e2));
    };
    t.a = flat(0);
    t.b = flat(1);
    t.c = flat(2);
    t.p = p;
    const double area =
        0.5 * std::abs((t.b - t.a).x() * (t.c - t.a).y() - (t.b - t.a).y() * (t.c - t.a).x());
    if (area > 0.0) {
      sim_points.push_back((t.a + t.b + t.c) / 3.0);
      sim_weights.push_back(area);
    }
    triangles.push_back(t);
  }
  if (sim_points.empty()) {
    throw Error(ErrorKind::Input,
                "the simulated map has no footprint seen along the plate's normal", {},
                "a body in contact");
  }
  std::vector<Eigen::Vector2d> ref_points;
  const Eigen::MatrixXd& P = reference.pressure;
  const auto centre_of = [&](Eigen::Index r, Eigen::Index c) {
    return Eigen::Vector2d((static_cast<double>(c) + 0.5) * reference.pixel,
                           (static_cast<double>(r) + 0.5) * reference.pixel);
  };
  for (Eigen::Index r = 0; r < P.rows(); ++r) {
    for (Eigen::Index c = 0; c < P.cols(); ++c) {
      if (P(r, c) > 0.0) ref_points.push_back(centre_of(r, c));
    }
  }
  if (ref_points.empty())
    throw Error(ErrorKind::Input, "the template has no pressure", {}, "a pressure map");
  const Frame2 sim = principal_frame(sim_points, sim_weights);
  const FlatSampler sample(std::move(triangles));
  const Frame2 ref = principal_frame(ref_points, std::vector<double>(ref_points.size(), 1.0));

  TemplateComparison best;
  best.correlation = -2.0;
  for (int flips = 0; flips < 4; ++flips) {
    const Eigen::Vector2d sign(flips & 1 ? -1.0 : 1.0, flips & 2 ? -1.0 : 1.0);
    TemplateComparison c;
    c.simulated.pixel = reference.pixel;
    c.simulated.pressure = Eigen::MatrixXd::Zero(P.rows(), P.cols());
    std::vector<double> x, y;
    for (Eigen::Index r = 0; r < P.rows(); ++r) {
      for (Eigen::Index col = 0; col < P.cols(); ++col) {
        // Template pixel → the template's principal coordinates → the
        // simulation's (reversed and stretched) → its plane.
        // A sensor reads the mean over its pixel: kSub² points across it.
        double v = 0.0;
        for (int i = 0; i < kSub; ++i) {
          for (int j = 0; j < kSub; ++j) {
            const Eigen::Vector2d offset((i + 0.5) / kSub - 0.5, (j + 0.5) / kSub - 0.5);
            const Eigen::Vector2d local =
                ref.axes.transpose() * (centre_of(r, col) + reference.pixel * offset - ref.centre);
            Eigen::Vector2d s_local;
            for (int k = 0; k < 2; ++k)
              s_local[k] = sign[k] * local[k] * sim.spread[k] / ref.spread[k];
            v += sample(sim.centre + sim.axes * s_local);
          }
        }
        v /= kSub * kSub;
        c.simulated.pressure(r, col) = v;
        if (v > 0.0 || P(r, col) > 0.0) {
          x.push_back(v);
          y.push_back(P(r, col));
        }
      }
    }
    c.correlation = pearson(x, y);
    c.pixels = static_cast<Eigen::Index>(x.size());
    c.length_reversed = sign[0] < 0.0;
    c.width_reversed = sign[1] < 0.0;
    if (c.correlation > best.correlation) best = std::move(c);
  }
  best.template_peak = P.maxCoeff();
  best.simulated_peak = best.simulated.pressure.maxCoeff();
  best.length_scale = ref.spread[0] / sim.spread[0];
  best.width_scale = ref.spread[1] / sim.spread[1];
  return best;
}

void write_template_comparison_svg(const std::filesystem::path& path, const TemplateComparison& c,
                                   const PressureGrid& reference,
                                   const std::string& simulated_title,
                                   const std::string& reference_title) {
  const Eigen::Index rows = reference.pressure.rows(), cols = reference.pressure.cols();
  const double cell = std::clamp(480.0 / static_cast<double>(rows), 4.0, 16.0);
  const double margin = 20.0, gap = 40.0, caption = 110.0, bar = 14.0;
  const double panel_w = cell * static_cast<double>(cols),
               panel_h = cell * static_cast<double>(rows);
  const double width = 2.0 * margin + 2.0 * panel_w + gap + 2.0 * (bar + 50.0);
  const double height = margin + 30.0 + panel_h + caption;
  SvgWriter svg;
  svg.begin(width, height);
  svg.text(margin, margin + 4.0,
           fmt::format("pressure pattern: correlation r = {:.3f} over {} pixels", c.correlation,
                       c.pixels),
           15.0, "start");
  const auto panel = [&](const Eigen::MatrixXd& P, double x0, const std::string& title,
                         double peak) {
    const double y0 = margin + 30.0;
    svg << "<g class=\"map\">\n";
    for (Eigen::Index r = 0; r < rows; ++r) {
      for (Eigen::Index col = 0; col < cols; ++col) {
        const double v = P(r, col);
        // Row 0 at the bottom, as the grid's y runs up.
        const double x = x0 + cell * static_cast<double>(col);
        const double y = y0 + cell * static_cast<double>(rows - 1 - r);
        const std::string fill = v > 0.0 ? hex_color(viridis(v / peak)) : std::string("#e6e6e6");
        svg << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << cell << "\" height=\""
            << cell << "\" fill=\"" << fill << "\"/>\n";
      }
    }
    svg << "</g>\n";
    // Its colour bar, 0 to its peak.
    const double bx = x0 + panel_w + 8.0;
    for (int k = 0; k < 50; ++k) {
      const double t = (static_cast<double>(k) + 0.5) / 50.0;
      svg << "<rect class=\"colorbar\" x=\"" << bx << "\" y=\""
          << y0 + panel_h * (1.0 - (k + 1) / 50.0) << "\" width=\"" << bar << "\" height=\""
          << panel_h / 50.0 + 0.5 << "\" fill=\"" << hex_color(viridis(t)) << "\"/>\n";
    }
    svg.text(bx, y0 - 4.0, fmt::format("{:.0f} kPa", peak / 1e3), 11.0, "start");
    svg.text(bx, y0 + panel_h + 12.0, "0", 11.0, "start");
    svg << "<g class=\"caption\">\n";
    svg.text(x0, y0 + panel_h + 24.0, title, 13.0, "start");
    svg.text(x0, y0 + panel_h + 42.0,
             fmt::format("peak {:.0f} kPa (colours: 0 to the peak)", peak / 1e3), 11.0, "start");
    svg << "</g>\n";
  };
  panel(c.simulated.pressure, margin, simulated_title, std::max(c.simulated_peak, 1e-12));
  panel(reference.pressure, margin + panel_w + gap + bar + 50.0, reference_title,
        std::max(c.template_peak, 1e-12));
  svg << "<g class=\"caption\">\n";
  svg.text(margin, height - 30.0,
           fmt::format("aligned by principal axes: length ×{:.3f}{}, width ×{:.3f}{}; {} mm pixels",
                       c.length_scale, c.length_reversed ? " (reversed)" : "", c.width_scale,
                       c.width_reversed ? " (reversed)" : "", reference.pixel * 1e3),
           11.0, "start");
  svg << "</g>\n";
  svg.end();
  write_file_atomic(path, [&](std::ostream& os) { os << svg.str(); });
}

}  // namespace palpa::report
