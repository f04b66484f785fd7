// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Scattered-data interpolation over a triangle surface: values known at a few
// sample points near the surface (tissue depths at ultrasound sites, stiffness
// at poking sites, pressures at sensor cells) are spread to every vertex.
//
// Each sample is first located on the surface (its closest point; a sample
// farther than InterpolationOptions::max_distance is an input error naming
// it) and attached to the nearest corner of the triangle it lands in: its
// "sample vertex". The vertex field u then minimizes a smoothness energy
// subject to u = value at every sample vertex (exactly, to rounding):
//
//  - Harmonic:   min ½ uᵀ L u   (L the cotangent Laplacian). Reproduces
//                constants; where cotangent weights are non-negative (no
//                obtuse pairs) it obeys the maximum principle (no overshoot),
//                but has a cusp at each sample.
//  - Biharmonic: smooth at the samples and linearly precise: the best linear
//                function of position a + g·x (least squares over the sample
//                vertices) is fitted and subtracted, the residual is
//                interpolated with min ½ rᵀ L M⁻¹ L r (M the lumped mass
//                matrix), and a + g·x is added back at the vertices. Any linear
//                function of position is therefore reproduced exactly (its
//                residual is zero), which the plain biharmonic energy does not
//                do on a curved surface (Δx = −2Hn ≠ 0). Chosen over a Hessian
//                energy because it reuses L and M, keeps one sparse SPD solve,
//                and is exact rather than approximately linear-precise. With
//                fewer than 4 samples, or samples in a plane or on a line, the
//                linear part is fitted only along the directions the samples
//                span (minimum-norm least squares).
//
// Why vertices and not the exact sample points: reproducing a value exactly
// at a point inside a triangle forces the triangle's corners beyond it when the
// value is the largest (or smallest) sample, so "reproduced" and "within the
// samples' range" could not both hold. Moving a sample to a corner shifts it by
// at most one edge length; choose the surface resolution accordingly.
//
// Biharmonic interpolation can overshoot the samples' range; with
// clamp_to_sample_range (the default) every vertex value is clamped to
// [min, max] of that value column's samples (sample vertices are never
// changed by it; where the linear part extrapolates beyond the samples,
// clamping gives up exact linear reproduction there).
//
// The sample vertices are eliminated and the free block of the energy matrix
// is factored once (sparse Cholesky), so interpolating further value sets at
// the same sample positions (pressure frames) costs one back-substitution
// each: construct a SurfaceInterpolator once.
//
// Requirements (palpa::Error, kind Input, naming options.source): every
// connected part of the surface must hold at least one sample; no two samples
// may share a sample vertex (the message names both: refine the surface or
// merge them); every vertex must belong to a triangle.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "palpa/geometry/closest_point.hpp"
#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

enum class SurfaceInterpolation {
  Harmonic,    // min Dirichlet energy: no overshoot, reproduces constants
  Biharmonic,  // linearly precise biharmonic: smooth, reproduces linear functions of position
};

struct InterpolationOptions {
  SurfaceInterpolation method = SurfaceInterpolation::Biharmonic;
  // Largest accepted distance from a sample to the surface [m]; must be > 0.
  double max_distance = 5e-3;
  // Clamp each interpolated column to its samples' [min, max].
  bool clamp_to_sample_range = true;
  // Names the samples' origin in error messages (usually the CSV file).
  std::string source;
  // Optional #S labels for error messages ("row 4", "A3"); default "sample i"
  // (0-based).
  std::vector<std::string> sample_labels;
};

class SurfaceInterpolator {
 public:
  // Locates the #S samples (rows of sample_positions [m]) on `mesh` and
  // factors the interpolation system. The mesh is copied (the interpolator
  // does not refer to it afterwards). Throws palpa::Error (Input) as described
  // above; (Solver) if the factorization fails for a reason other than input.
  SurfaceInterpolator(const SurfaceMesh& mesh, const Eigen::MatrixX3d& sample_positions,
                      const InterpolationOptions& options = {});
  ~SurfaceInterpolator();
  SurfaceInterpolator(SurfaceInterpolator&&) noexcept;
  SurfaceInterpolator& operator=(SurfaceInterpolator&&) noexcept;

  // values: #S, one per sample (any unit). Returns #V vertex values (same
  // unit). Throws palpa::Error (Input) for a size other than #S or a
  // non-finite value (naming the sample). Thread-safe (const, no scratch).
  Eigen::VectorXd interpolate(const Eigen::VectorXd& values) const;
  // The same for k fields at once: values #S×k, returns #V×k (each column
  // clamped to its own samples' range).
  Eigen::MatrixXd interpolate_columns(const Eigen::MatrixXd& values) const;

  // The located samples (closest surface points), in input order.
  const std::vector<SurfacePoint>& sample_points() const noexcept;
  // The vertex each sample is attached to (row of V), in input order.
  const std::vector<Eigen::Index>& sample_vertices() const noexcept;
  Eigen::Index vertex_count() const noexcept;
  Eigen::Index sample_count() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot: SurfaceInterpolator(mesh, sample_positions, options).interpolate(values).
Eigen::VectorXd interpolate_over_surface(const SurfaceMesh& mesh,
                                         const Eigen::MatrixX3d& sample_positions,
                                         const Eigen::VectorXd& values,
                                         const InterpolationOptions& options = {});

}  // namespace palpa::geometry
