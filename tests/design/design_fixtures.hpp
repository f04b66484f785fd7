// SPDX-License-Identifier: AGPL-3.0-or-later
// The soft blocks, slabs and options the design tests share.
#pragma once

#include <vector>

#include "palpa/design/optimizer.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design::fixture {

constexpr double kRho = 1000.0, kH = 0.02, kW = 0.04;

// A 40 × 40 × 20 mm soft block hanging from its top face (the core), its
// bottom 0.4 mm above z = 0, shifted off the slab's grid.
rest::RestBody block(int n = 6);
// The body on the linear tet: at ν 0.3 it does not lock, and it is 2–3×
// cheaper than the default nodal-pressure tet, which the adjoint checks use.
rest::RestBody on_linear_tets(rest::RestBody b);
// A 70 × 70 × 10 mm slab, top face at z = 0.
SurfaceMesh slab(int divisions = 14);
// The slab with its sides cut into squares too (`divisions` across, 2 up),
// so that the tets inside a deformable one are well shaped.
SurfaceMesh foam_slab(int divisions = 14);
// Top-face vertices of the slab strictly inside its rim.
std::vector<int> top_inside(const SurfaceMesh& s, double half = 0.03);
// The core of 0.5 kg free to sink (and, with `rotate`, to tilt).
rest::RestOptions options(bool rotate = false);
// A foam slab (E 40 kPa, twice the body's, by default), meshed with 5 mm tets.
rest::RestOptions on_foam(rest::RestOptions o, double E = 40e3);
// A centred cushion: the block with its bottom curved by `bulge` between
// centre and corners (the top, on the core, stays flat). bulge > 0: the
// centre hangs lowest and touches first; bulge < 0: a dish, its corners
// touch first.
rest::RestBody cushion(double bulge, int n = 8);
// ‖m − mirror(m)‖ / ‖m‖ for a field m on the slab's vertices, mirror the
// reflection in the plane x = y.
double mirror_asymmetry(const SurfaceMesh& s, const Eigen::MatrixX3d& moved);
// The 6 mm cushion on `s`, its top moved along the normals; φ must fall at
// every accepted iteration. foam > 0: the slab is a foam of that modulus.
DesignResult cushion_design(const SurfaceMesh& s, DesignMethod method, int iterations, int post_smoothing,
                            double foam = 0.0);

}  // namespace palpa::design::fixture
