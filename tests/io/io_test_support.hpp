// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Shared fixtures for the io tests: small meshes with known contents, exact
// (bitwise) comparisons, file helpers and a runner for the system Python that
// has meshio (an independent reader/writer of the same formats).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <filesystem>
#include <random>
#include <string>

#include "palpa/geometry/mesh.hpp"

namespace palpa::test {

// A surface with `nv` vertices of random doubles (full mantissas, magnitudes
// from 1e-6 to 1 m, both signs) and `nf` random triangles with distinct corners.
SurfaceMesh random_surface(std::mt19937_64& rng, int nv, int nf);

// The unit cube [0,1]^3 as 8 vertices and 12 outward triangles.
SurfaceMesh unit_cube_surface();

// The unit cube split into 6 tets around the diagonal (0,0,0)-(1,1,1), regions
// 1,2,1,2,1,2 (interleaved), 12 boundary triangles with markers 1..6 (one per
// cube side), vertices moved by random sub-millimetre offsets so coordinates
// have full mantissas.
TetMesh cube_tet_mesh(std::mt19937_64& rng);

// True when a and b have the same shape and identical bits in every entry
// (so 0.0 and -0.0 differ and any rounding is caught).
::testing::AssertionResult same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);
::testing::AssertionResult same_ints(const Eigen::MatrixXi& a, const Eigen::MatrixXi& b);

std::string read_bytes(const std::filesystem::path& p);
void write_bytes(const std::filesystem::path& p, const std::string& bytes);

// Runs `/usr/bin/python3 <script file>` with `script` as its text; returns the
// exit status and fills `out` with stdout+stderr.
int run_python(const std::string& script, std::string& out);
// True when /usr/bin/python3 can import meshio.
bool meshio_available();

}  // namespace palpa::test
