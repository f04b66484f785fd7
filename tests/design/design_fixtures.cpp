// SPDX-License-Identifier: AGPL-3.0-or-later
#include "design_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "palpa/material/models.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::design::fixture {

rest::RestBody block(int n) {
  rest::RestBody b;
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-kW / 2 + 1.3e-3, -kW / 2 + 0.7e-3, 4e-4),
                                        Eigen::Vector3d(kW / 2 + 1.3e-3, kW / 2 + 0.7e-3, kH + 4e-4),
                                        Eigen::Vector3i(n, n, n / 2));
  b.mesh = box.mesh;
  b.attached = box.vertex_sets.at("top");
  b.materials = {{std::make_shared<material::NeoHookean>(20e3, 0.3), kRho}};
  return b;
}

rest::RestBody on_linear_tets(rest::RestBody b) {
  b.element = {tet::TetElement::Linear, 0.0};
  return b;
}

SurfaceMesh slab(int divisions) {
  SurfaceMesh s = sim3d::make_box_surface(Eigen::Vector3d(0.07, 0.07, 0.01), divisions);
  s.V.col(2).array() -= 0.01;
  return s;
}

SurfaceMesh foam_slab(int divisions) {
  SurfaceMesh s = sim3d::make_box_surface(Eigen::Vector3d(0.07, 0.07, 0.01), Eigen::Vector3i(divisions, divisions, 2));
  s.V.col(2).array() -= 0.01;
  return s;
}

std::vector<int> top_inside(const SurfaceMesh& s, double half) {
  std::vector<int> v;
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    if (s.V(i, 2) > -6e-4 && std::abs(s.V(i, 0)) < half && std::abs(s.V(i, 1)) < half) {
      v.push_back(static_cast<int>(i));
    }
  }
  return v;
}

rest::RestOptions options(bool rotate) {
  rest::RestOptions o;
  o.core.mass = 0.5;
  o.core.locked = {true, true, false, !rotate, !rotate, true};
  o.force_tolerance = 1e-10;
  return o;
}

rest::RestOptions on_foam(rest::RestOptions o, double E) {
  o.deformable_support = rest::DeformableSupport{std::make_shared<material::NeoHookean>(E, 0.3), 5e-3, 1e-4};
  return o;
}

rest::RestBody cushion(double bulge, int n) {
  rest::RestBody b;
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-kW / 2, -kW / 2, 4e-4), Eigen::Vector3d(kW / 2, kW / 2, kH + 4e-4),
                                        Eigen::Vector3i(n, n, n / 2));
  for (Eigen::Index v = 0; v < box.mesh.V.rows(); ++v) {
    const double r2 = (box.mesh.V(v, 0) * box.mesh.V(v, 0) + box.mesh.V(v, 1) * box.mesh.V(v, 1)) / (kW * kW / 2);
    const double t = (kH + 4e-4 - box.mesh.V(v, 2)) / kH;  // 1 at the bottom, 0 at the top
    box.mesh.V(v, 2) += t * (bulge > 0.0 ? bulge * r2 : -bulge * (1.0 - r2));
  }
  b.mesh = box.mesh;
  b.attached = box.vertex_sets.at("top");
  b.materials = {{std::make_shared<material::NeoHookean>(20e3, 0.3), kRho}};
  return on_linear_tets(b);
}

double mirror_asymmetry(const SurfaceMesh& s, const Eigen::MatrixX3d& moved) {
  double asymmetry = 0.0;
  for (Eigen::Index v = 0; v < s.V.rows(); ++v) {
    for (Eigen::Index w = 0; w < s.V.rows(); ++w) {
      if (std::abs(s.V(w, 0) - s.V(v, 1)) < 1e-9 && std::abs(s.V(w, 1) - s.V(v, 0)) < 1e-9 &&
          std::abs(s.V(w, 2) - s.V(v, 2)) < 1e-9) {
        asymmetry += (moved.row(v) - Eigen::RowVector3d(moved(w, 1), moved(w, 0), moved(w, 2))).squaredNorm();
      }
    }
  }
  return std::sqrt(asymmetry) / moved.norm();
}

DesignResult cushion_design(const SurfaceMesh& s, DesignMethod method, int iterations, int post_smoothing,
                            double foam) {
  DesignOptions o;
  o.method = method;
  o.max_iterations = iterations;
  o.post_smoothing = post_smoothing;
  o.normal_only = true;
  o.smoothing_exponent = -2.0;
  ShapeOptimizer opt(cushion(6e-3), s, foam > 0.0 ? on_foam(options(), foam) : options(), top_inside(s), o);
  DesignResult r = opt.run();
  double previous = r.initial.phi;
  for (const IterationRecord& it : r.history) {
    EXPECT_LT(it.phi, previous) << "iteration " << it.iteration;
    previous = it.phi;
  }
  return r;
}

}  // namespace palpa::design::fixture
