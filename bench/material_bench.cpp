// SPDX-License-Identifier: AGPL-3.0-or-later
// Element-level throughput of the material kernels: energy + gradient + Hessian
// per second for a linear tetrahedron (3D) and a bilinear axisymmetric quad
// (9 Gauss points), for neo-Hookean and the spline material. Reference in the
// same run: a neo-Hookean tetrahedron written directly in F (no SVD), the usual
// closed form P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ with its tangent.
// Prints one JSON line per figure.

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "bench_util.hpp"
#include "palpa/material/kinematics.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace {

using namespace palpa::material;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

// dvec(F)/dx for a linear tet: F = Ds Dm⁻¹, x = 4 nodes × 3.
Eigen::Matrix<double, 9, 12> tet_b(const Mat3& dm_inv) {
  Eigen::Matrix<double, 9, 12> b = Eigen::Matrix<double, 9, 12>::Zero();
  // Shape gradients: node 0 is −sum of the others.
  for (int col = 0; col < 3; ++col) {      // column of F
    for (int node = 1; node < 4; ++node) {
      const double g = dm_inv(node - 1, col);
      for (int row = 0; row < 3; ++row) {
        b(row + 3 * col, 3 * node + row) += g;
        b(row + 3 * col, row) -= g;
      }
    }
  }
  return b;
}

struct Tet {
  Eigen::Matrix<double, 3, 4> x;
  Mat3 dm_inv;
  double volume;
  Eigen::Matrix<double, 9, 12> b;
};

std::vector<Tet> make_tets(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  std::vector<Tet> tets;
  Eigen::Matrix<double, 3, 4> rest;
  rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  rest *= 1e-3;
  Mat3 dm;
  for (int c = 0; c < 3; ++c) dm.col(c) = rest.col(c + 1) - rest.col(0);
  for (int i = 0; i < n; ++i) {
    Tet t;
    t.dm_inv = dm.inverse();
    t.volume = std::abs(dm.determinant()) / 6.0;
    t.b = tet_b(t.dm_inv);
    t.x = rest;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) t.x(r, c) += 1e-3 * u(rng);
    tets.push_back(t);
  }
  return tets;
}

Mat3 deformation(const Tet& t) {
  Mat3 ds;
  for (int c = 0; c < 3; ++c) ds.col(c) = t.x.col(c + 1) - t.x.col(0);
  return ds * t.dm_inv;
}

double tet_kernel(const Material& m, const Tet& t, Vec12& g, Mat12& h) {
  Stress3 s;
  stress(m, deformation(t), EvalOrder::Hessian, PsdProjection::Clamp, s);
  const Eigen::Map<const Vec9> p(s.P.data());
  g.noalias() = t.volume * t.b.transpose() * p;
  h.noalias() = t.volume * t.b.transpose() * s.dPdF * t.b;
  return t.volume * s.psi;
}

// Direct neo-Hookean in F (reference): P and dP/dF without an SVD.
double tet_kernel_direct(double mu, double lambda, const Tet& t, Vec12& g, Mat12& h) {
  const Mat3 F = deformation(t);
  const double j = F.determinant();
  const Mat3 finv = F.inverse();
  const Mat3 fit = finv.transpose();
  const double lj = std::log(j);
  const Mat3 P = mu * (F - fit) + lambda * lj * fit;
  Mat9 d;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      for (int jj = 0; jj < 3; ++jj)
        for (int i = 0; i < 3; ++i) {
          double v = (mu - lambda * lj) * finv(l, i) * finv(jj, k) + lambda * finv(jj, i) * finv(l, k);
          if (i == k && jj == l) v += mu;
          d(i + 3 * jj, k + 3 * l) = v;
        }
  const Eigen::Map<const Vec9> p(P.data());
  g.noalias() = t.volume * t.b.transpose() * p;
  h.noalias() = t.volume * t.b.transpose() * d * t.b;
  return t.volume * (0.5 * mu * ((F.transpose() * F).trace() - 3.0) - mu * lj + 0.5 * lambda * lj * lj);
}

// Axisymmetric bilinear quad, 3×3 Gauss points: per point the (r, z) gradient,
// the hoop stretch 1 + u_r/r and the 5×8 map to the element DOFs.
struct Quad {
  Eigen::Matrix<double, 2, 4> x;  // rest (r, z)
  Eigen::Matrix<double, 2, 4> u;  // displacement
};

double quad_kernel(const Material& m, const Quad& q, Eigen::Matrix<double, 8, 1>& g,
                   Eigen::Matrix<double, 8, 8>& h) {
  static constexpr double kGp[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static constexpr double kGw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  g.setZero();
  h.setZero();
  double energy = 0.0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const double xi = kGp[a];
      const double eta = kGp[b];
      const Eigen::Vector4d n(0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta),
                              0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta));
      Eigen::Matrix<double, 4, 2> dn;
      dn << -0.25 * (1 - eta), -0.25 * (1 - xi), 0.25 * (1 - eta), -0.25 * (1 + xi),
          0.25 * (1 + eta), 0.25 * (1 + xi), -0.25 * (1 + eta), 0.25 * (1 - xi);
      const Mat2 jac = q.x * dn;
      const Eigen::Matrix<double, 4, 2> dndx = dn * jac.inverse();
      const double r = q.x.row(0).dot(n);
      const Mat2 F2 = Mat2::Identity() + q.u * dndx;
      const double hoop = 1.0 + q.u.row(0).dot(n) / r;
      Eigen::Matrix<double, 5, 8> bm = Eigen::Matrix<double, 5, 8>::Zero();
      for (int k = 0; k < 4; ++k) {
        bm(0, 2 * k) = dndx(k, 0);      // F_rr ← u_r
        bm(1, 2 * k + 1) = dndx(k, 0);  // F_zr ← u_z
        bm(2, 2 * k) = dndx(k, 1);      // F_rz ← u_r
        bm(3, 2 * k + 1) = dndx(k, 1);  // F_zz ← u_z
        bm(4, 2 * k) = n[k] / r;        // F_θθ ← u_r
      }
      StressAxisym s;
      stress_axisymmetric(m, F2, hoop, EvalOrder::Hessian, PsdProjection::Clamp, s);
      const double w = 2.0 * M_PI * r * kGw[a] * kGw[b] * std::abs(jac.determinant());
      energy += w * s.psi;
      g.noalias() += w * bm.transpose() * s.P;
      h.noalias() += w * bm.transpose() * s.dPdF * bm;
    }
  }
  return energy;
}

}  // namespace

int main() {
  const double e = 12e3;
  const double nu = 0.45;
  const NeoHookean nh(e, nu);
  const SplineMaterial spline = SplineMaterial::from_model(nh);
  const ElasticConstants lame = lame_from_young(e, nu);
  const std::vector<Tet> tets = make_tets(256);

  Vec12 g;
  Mat12 h;
  double sink = 0.0;
  const double direct = palpa::bench::throughput(
      [&] {
        for (const Tet& t : tets) sink += tet_kernel_direct(lame.mu, lame.lambda, t, g, h);
      },
      static_cast<double>(tets.size()));

  // Accuracy: the SVD route against the direct formula.
  double worst = 0.0;
  for (const Tet& t : tets) {
    Vec12 g1;
    Mat12 h1;
    Vec12 g2;
    Mat12 h2;
    Stress3 s;
    stress(nh, deformation(t), EvalOrder::Hessian, PsdProjection::None, s);
    const Eigen::Map<const Vec9> p(s.P.data());
    g1 = t.volume * t.b.transpose() * p;
    h1 = t.volume * t.b.transpose() * s.dPdF * t.b;
    tet_kernel_direct(lame.mu, lame.lambda, t, g2, h2);
    worst = std::max(worst, (h1 - h2).cwiseAbs().maxCoeff() / h2.cwiseAbs().maxCoeff());
  }

  for (const Material* m : {static_cast<const Material*>(&nh), static_cast<const Material*>(&spline)}) {
    const double rate = palpa::bench::throughput(
        [&] {
          for (const Tet& t : tets) sink += tet_kernel(*m, t, g, h);
        },
        static_cast<double>(tets.size()));
    palpa::bench::emit({{"bench", "material.tet_element"},
                        {"model", std::string(m->model())},
                        {"figure", "energy+gradient+PSD Hessian per second (1 thread)"},
                        {"elements_per_s", rate},
                        {"reference", "direct neo-Hookean in F, no SVD, unprojected"},
                        {"reference_elements_per_s", direct},
                        {"ratio_to_reference", rate / direct},
                        {"accuracy_max_rel_hessian_diff_vs_direct", worst}});
  }

  std::vector<Quad> quads;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int i = 0; i < 64; ++i) {
    Quad q;
    const double r0 = 1e-3 * (1 + i % 8);
    q.x << r0, r0 + 1e-3, r0 + 1e-3, r0, -1e-3, -1e-3, 0.0, 0.0;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 2; ++r) q.u(r, c) = 1e-3 * u(rng);
    quads.push_back(q);
  }
  Eigen::Matrix<double, 8, 1> gq;
  Eigen::Matrix<double, 8, 8> hq;
  for (const Material* m : {static_cast<const Material*>(&nh), static_cast<const Material*>(&spline)}) {
    const double rate = palpa::bench::throughput(
        [&] {
          for (const Quad& q : quads) sink += quad_kernel(*m, q, gq, hq);
        },
        static_cast<double>(quads.size()));
    palpa::bench::emit({{"bench", "material.axisym_quad_element"},
                        {"model", std::string(m->model())},
                        {"figure", "energy+gradient+PSD Hessian per second, 9 Gauss points (1 thread)"},
                        {"elements_per_s", rate},
                        {"gauss_points_per_s", 9.0 * rate},
                        {"reference", "direct neo-Hookean tet (per element)"},
                        {"reference_elements_per_s", direct},
                        {"ratio_gauss_point_to_reference_tet", 9.0 * rate / direct}});
  }
  if (sink == 42.0) fmt::print("\n");  // keep the results alive
  return 0;
}
