// SPDX-License-Identifier: AGPL-3.0-or-later
#include "io/io_test_support.hpp"

#include <fmt/format.h>
#include <sys/wait.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "common/test_support.hpp"

namespace palpa::test {

SurfaceMesh random_surface(std::mt19937_64& rng, int nv, int nf) {
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 0);
  SurfaceMesh m;
  m.V.resize(nv, 3);
  for (int i = 0; i < nv; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double digits = mantissa(rng);  // drawn before the exponent on every compiler
      m.V(i, c) = digits * std::pow(10.0, exponent(rng));
    }
  }
  std::uniform_int_distribution<int> pick(0, nv - 1);
  m.F.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    while (b == a) b = pick(rng);
    while (c == a || c == b) c = pick(rng);
    m.F.row(f) << a, b, c;
  }
  return m;
}

SurfaceMesh unit_cube_surface() {
  SurfaceMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.F.resize(12, 3);
  // Each side split along the diagonal through vertex 0 or 7, as the tets of
  // cube_tet_mesh() split it; outward winding.
  m.F << 0, 3, 1, 0, 2, 3,  // z = 0
      4, 5, 7, 4, 7, 6,     // z = 1
      0, 1, 5, 0, 5, 4,     // y = 0
      2, 7, 3, 2, 6, 7,     // y = 1
      0, 4, 6, 0, 6, 2,     // x = 0
      1, 3, 7, 1, 7, 5;     // x = 1
  return m;
}

TetMesh cube_tet_mesh(std::mt19937_64& rng) {
  const SurfaceMesh cube = unit_cube_surface();
  TetMesh m;
  m.V = cube.V;
  std::uniform_real_distribution<double> jitter(-1e-4, 1e-4);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    for (int c = 0; c < 3; ++c) m.V(i, c) = 0.01 * m.V(i, c) + jitter(rng);
  }
  // Six tets sharing the diagonal 0-7 (one per path 0 -> 7 along the axes).
  m.T.resize(6, 4);
  m.T << 0, 1, 3, 7,  //
      0, 2, 3, 7,     //
      0, 2, 6, 7,     //
      0, 4, 6, 7,     //
      0, 4, 5, 7,     //
      0, 1, 5, 7;
  m.region.resize(6);
  m.region << 1, 2, 1, 2, 1, 2;
  m.boundary = cube.F;
  m.boundary_marker.resize(12);
  m.boundary_marker << 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6;
  return m;
}

::testing::AssertionResult same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "shapes differ: " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      if (std::bit_cast<std::uint64_t>(a(i, j)) != std::bit_cast<std::uint64_t>(b(i, j))) {
        return ::testing::AssertionFailure()
               << fmt::format("entry ({}, {}) differs: {} vs {}", i, j, a(i, j), b(i, j));
      }
    }
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult same_ints(const Eigen::MatrixXi& a, const Eigen::MatrixXi& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "shapes differ: " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      if (a(i, j) != b(i, j)) {
        return ::testing::AssertionFailure()
               << fmt::format("entry ({}, {}) differs: {} vs {}", i, j, a(i, j), b(i, j));
      }
    }
  }
  return ::testing::AssertionSuccess();
}

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

int run_python(const std::string& script, std::string& out) {
  ScratchDir dir;
  const auto script_path = dir.write("check.py", script);
  const auto output = dir / "output.txt";
  const std::string cmd =
      fmt::format("/usr/bin/python3 '{}' >'{}' 2>&1", script_path.string(), output.string());
  const int status = std::system(cmd.c_str());
  out = read_bytes(output);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool meshio_available() {
  std::string out;
  return std::filesystem::exists("/usr/bin/python3") &&
         run_python("import meshio\nprint('ok')\n", out) == 0;
}

}  // namespace palpa::test
