// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmarks of the solve module. Prints one JSON line per figure (see
// BENCHMARKS.md): each figure with its in-run reference and the ratio.
//
//  1. Sparse factorizations on 2D-Laplacian and 3D-elasticity-like SPD matrices
//     at four sizes: time of the symbolic analysis, of one numeric
//     factorization and of one solve, for CHOLMOD supernodal, CHOLMOD
//     simplicial, CHOLMOD auto (palpa's default) and Eigen's SimplicialLDLT.
//     Reference: CHOLMOD auto, same matrix, same phase. Problems: the 2D
//     Laplacian, a 2D elasticity-like pattern (2 DOFs per node, the
//     axisymmetric solver's) and a 3D one; per matrix also the flops per
//     nonzero of L that the automatic choice compares with its switch, beside
//     simplicial / supernodal factorization time. Accuracy: the relative
//     residual ‖Ax − b‖/‖b‖. Then the fitted exponent of time ∝ n^p per solver
//     and phase.
//  2. Newton on a pulled 2D spring mesh (about 30% stretch) at four sizes:
//     wall time, iterations, factorizations; reference: one numeric
//     factorization of the Hessian at the solution; ratio "Newton / one
//     factorization". Accuracy: final ‖g‖∞ and the support reaction's error.
//
// Options: --quick runs the two smallest sizes only.

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/solve/sparse_cholesky.hpp"
#include "palpa/solve/sparse_ldlt.hpp"
#include "solve/matrices.hpp"
#include "solve/spring_network.hpp"

namespace {

using palpa::FactorStatus;
using palpa::SparseCholesky;
using palpa::SparseLdlt;
using palpa::SymmetricFactorization;
using SpMat = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

using palpa::bench::median_seconds;
using palpa::bench::seconds_since;

// Least-squares slope of log(y) against log(x).
double fitted_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0.0;
  double sy = 0.0;
  double sxx = 0.0;
  double sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]);
    const double ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

struct SolverSpec {
  std::string name;
  std::function<std::unique_ptr<SymmetricFactorization>()> make;
};

std::vector<SolverSpec> solvers() {
  return {
      {"cholmod-auto",
       [] { return std::make_unique<SparseCholesky>(SparseCholesky::Method::Auto); }},
      {"cholmod-supernodal",
       [] { return std::make_unique<SparseCholesky>(SparseCholesky::Method::Supernodal); }},
      {"cholmod-simplicial",
       [] { return std::make_unique<SparseCholesky>(SparseCholesky::Method::Simplicial); }},
      {"eigen-simplicial-ldlt", [] { return std::make_unique<SparseLdlt>(); }},
  };
}

struct PhaseTimes {
  double analyze = 0.0;
  double factorize = 0.0;
  double solve = 0.0;
  double residual = 0.0;
};

PhaseTimes time_solver(const SolverSpec& spec, const SpMat& A_full, const SpMat& A_lower,
                       const Eigen::VectorXd& b) {
  PhaseTimes p;
  std::unique_ptr<SymmetricFactorization> f;
  p.analyze = median_seconds([&] { f = spec.make(); }, [&] { (void)f->analyze(A_lower); });
  p.factorize = median_seconds([] {},
                               [&] {
                                 if (f->factorize(A_lower) != FactorStatus::Ok)
                                   throw std::runtime_error("factorization failed");
                               });
  Eigen::VectorXd x;
  p.solve = median_seconds([] {}, [&] { x = f->solve(b); });
  p.residual = (A_full * x - b).norm() / b.norm();
  return p;
}

void print_figure(const std::string& figure, const std::string& problem, Eigen::Index n,
                  Eigen::Index nnz, const std::string& solver, double seconds,
                  const std::string& reference, double reference_seconds, double residual) {
  fmt::print(
      "{{\"bench\":\"solve\",\"figure\":\"{}\",\"problem\":\"{}\",\"n\":{},\"nnz\":{},"
      "\"solver\":\"{}\",\"seconds\":{:.6g},\"reference\":\"{}\",\"reference_seconds\":{:.6g},"
      "\"ratio\":{:.4g},\"residual\":{:.3g}}}\n",
      figure, problem, n, nnz, solver, seconds, reference, reference_seconds,
      seconds / reference_seconds, residual);
  std::fflush(stdout);
}

void bench_factorizations(const std::string& problem, const std::vector<int>& sizes,
                          const std::function<SpMat(int)>& make_matrix) {
  const std::vector<SolverSpec> specs = solvers();
  // [solver][phase] -> times per size; n per size.
  std::map<std::string, std::map<std::string, std::vector<double>>> times;
  std::vector<double> ns;
  for (int m : sizes) {
    const SpMat A = make_matrix(m);
    const SpMat L = palpa::test::lower_triangle(A);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), 1.0, 2.0);
    ns.push_back(static_cast<double>(A.rows()));
    std::map<std::string, PhaseTimes> results;
    for (const SolverSpec& s : specs) results[s.name] = time_solver(s, A, L, b);
    const PhaseTimes& ref = results.at("cholmod-auto");
    // The quantity the automatic choice looks at, beside the two numeric
    // factorization times it chooses between.
    SparseCholesky probe;
    if (probe.analyze(L) != FactorStatus::Ok) throw std::runtime_error("analysis failed");
    const double simplicial = results.at("cholmod-simplicial").factorize;
    const double supernodal = results.at("cholmod-supernodal").factorize;
    fmt::print(
        "{{\"bench\":\"solve\",\"figure\":\"simplicial_vs_supernodal\",\"problem\":\"{}\",\"n\":{},"
        "\"flops_per_lnz\":{:.4g},\"simplicial_seconds\":{:.6g},\"supernodal_seconds\":{:.6g},"
        "\"ratio\":{:.4g},\"auto\":\"{}\"}}\n",
        problem, A.rows(), probe.factor_flops() / probe.factor_nonzeros(), simplicial, supernodal,
        simplicial / supernodal, probe.is_supernodal() ? "supernodal" : "simplicial");
    for (const SolverSpec& s : specs) {
      const PhaseTimes& p = results.at(s.name);
      print_figure("analyze", problem, A.rows(), L.nonZeros(), s.name, p.analyze,
                   "cholmod-auto.analyze", ref.analyze, p.residual);
      print_figure("factorize", problem, A.rows(), L.nonZeros(), s.name, p.factorize,
                   "cholmod-auto.factorize", ref.factorize, p.residual);
      print_figure("solve", problem, A.rows(), L.nonZeros(), s.name, p.solve, "cholmod-auto.solve",
                   ref.solve, p.residual);
      times[s.name]["analyze"].push_back(p.analyze);
      times[s.name]["factorize"].push_back(p.factorize);
      times[s.name]["solve"].push_back(p.solve);
    }
  }
  if (ns.size() < 2) return;
  for (const auto& [solver, phases] : times) {
    for (const auto& [phase, t] : phases) {
      fmt::print(
          "{{\"bench\":\"solve\",\"figure\":\"scaling_exponent\",\"problem\":\"{}\","
          "\"solver\":\"{}\",\"phase\":\"{}\",\"exponent\":{:.3f},\"n_min\":{},\"n_max\":{},"
          "\"seconds_min\":{:.4g},\"seconds_max\":{:.4g}}}\n",
          problem, solver, phase, fitted_exponent(ns, t), ns.front(), ns.back(), t.front(),
          t.back());
    }
  }
  std::fflush(stdout);
}

// A spring mesh of nx × ny nodes (1 mm spacing, 100 N/m springs) pinned on its
// left edge and pulled on its right edge to about 30% stretch.
palpa::test::SpringNetwork pulled_mesh(int nx, int ny, double& total_force) {
  constexpr double kSpacing = 1e-3;
  constexpr double kStiffness = 100.0;
  auto net = palpa::test::SpringNetwork::grid(nx, ny, kSpacing, kStiffness);
  // The mesh's axial stiffness grows with its height and falls with its length.
  total_force = 0.3 * (ny - 1) / 5.0 * 11.0 / (nx - 1);
  const double per_node = total_force / (ny - 1);
  for (int j = 0; j < ny; ++j) {
    const double share = (j == 0 || j == ny - 1) ? 0.5 * per_node : per_node;
    net.set_force(nx - 1 + nx * j, Eigen::Vector2d(share, 0.0));
  }
  return net;
}

void bench_newton(const std::vector<int>& heights) {
  std::vector<double> ns;
  std::vector<double> newton_seconds;
  for (int ny : heights) {
    const int nx = 2 * ny;
    double total = 0.0;
    auto net = pulled_mesh(nx, ny, total);
    palpa::NewtonOptions o;
    o.gradient_abs_tol = 1e-10 * total;
    o.gradient_rel_tol = 0.0;

    // Wall time of a full solve from the rest state on a fresh solver
    // (analysis included), median of repetitions.
    palpa::NewtonResult r;
    Eigen::VectorXd x;
    std::unique_ptr<palpa::NewtonSolver> solver;
    const double wall = median_seconds(
        [&] {
          solver = std::make_unique<palpa::NewtonSolver>(o);
          x = net.reference_dofs();
        },
        [&] { r = solver->solve(net, x); });
    if (!r.converged()) throw std::runtime_error("newton did not converge: " + r.message);

    // Reference: one numeric factorization of the Hessian at the solution.
    SpMat H;
    net.hessian(x, H);
    SparseCholesky chol;
    (void)chol.analyze(H);
    const double factor = median_seconds([] {}, [&] { (void)chol.factorize(H); });
    const double reaction_error = std::abs(net.support_reaction(x).x() + total) / total;

    const Eigen::Index n = net.num_dofs();
    fmt::print(
        "{{\"bench\":\"solve\",\"figure\":\"newton_seconds\",\"problem\":\"spring_mesh_{}x{}\","
        "\"n\":{},\"nnz\":{},\"solver\":\"newton+cholmod-auto\",\"seconds\":{:.6g},"
        "\"reference\":\"one cholmod-auto factorization of H(x*)\",\"reference_seconds\":{:.6g},"
        "\"ratio\":{:.4g},\"iterations\":{},\"factorizations\":{},\"energy_evaluations\":{},"
        "\"gradient_norm\":{:.3g},\"gradient_tolerance\":{:.3g},\"reaction_rel_error\":{:.3g}}}\n",
        nx, ny, n, H.nonZeros(), wall, factor, wall / factor, r.iterations, r.factorizations,
        r.energy_evaluations, r.gradient_norm, r.gradient_tolerance, reaction_error);
    std::fflush(stdout);
    ns.push_back(static_cast<double>(n));
    newton_seconds.push_back(wall);
  }
  if (ns.size() >= 2) {
    fmt::print(
        "{{\"bench\":\"solve\",\"figure\":\"scaling_exponent\",\"problem\":\"spring_mesh\","
        "\"solver\":\"newton+cholmod-auto\",\"phase\":\"newton\",\"exponent\":{:.3f},"
        "\"n_min\":{},\"n_max\":{},\"seconds_min\":{:.4g},\"seconds_max\":{:.4g}}}\n",
        fitted_exponent(ns, newton_seconds), ns.front(), ns.back(), newton_seconds.front(),
        newton_seconds.back());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  auto first = [quick](std::vector<int> v) {
    if (quick) v.resize(2);
    return v;
  };
  try {
    bench_factorizations("laplacian_2d", first({64, 128, 256, 512}), palpa::test::laplacian_2d);
    bench_factorizations("elasticity_2d_like", first({48, 96, 192, 384}),
                         [](int m) { return palpa::test::elasticity_2d_like(m); });
    bench_factorizations("elasticity_3d_like", first({6, 9, 12, 16}),
                         [](int m) { return palpa::test::elasticity_3d_like(m); });
    bench_newton(first({16, 32, 64, 128}));
  } catch (const std::exception& e) {
    fmt::print(stderr, "palpa_bench_solve: {}\n", e.what());
    return 1;
  }
  return 0;
}
