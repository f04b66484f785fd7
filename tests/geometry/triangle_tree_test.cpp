// SPDX-License-Identifier: AGPL-3.0-or-later
// The triangle tree: closest points against an exhaustive scan on an icosphere
// and on a thin two-layer sheet, the reported feature and weights, ties to the
// lowest triangle index, refit against rebuild, concurrent queries, the empty
// tree.

#include "palpa/geometry/triangle_tree.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "common/test_support.hpp"
#include "geometry/test_surfaces.hpp"

namespace palpa::geometry {
namespace {

// The closest triangle by an exhaustive scan (ties: the lowest index).
TriangleTree::Hit scan_closest(const SurfaceMesh& mesh, const Eigen::Vector3d& p) {
  TriangleTree::Hit best;
  for (int f = 0; f < static_cast<int>(mesh.F.rows()); ++f) {
    const TrianglePoint tp = closest_on_triangle(
        p, mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)));
    const double d2 = (p - tp.point).squaredNorm();
    if (d2 < best.distance2) best = {f, d2, tp};
  }
  return best;
}

Eigen::Vector3d uniform_point(std::mt19937_64& rng, const Eigen::Vector3d& half) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double x = u(rng), y = u(rng), z = u(rng);  // drawn in order on every compiler
  return Eigen::Vector3d(x, y, z).cwiseProduct(half);
}

// 0: a corner, 1: an edge interior, 2: the face interior.
int feature_kind(int region) {
  return region < kEdgeAB ? 0 : (region < kFace ? 1 : 2);
}

// The hit is a point of its triangle: weights ≥ 0 summing to 1, with the zeros
// its region says (a corner: the other two; an edge: the opposite corner;
// the face: none), and point = Σ_k w_k V(F(triangle, k)).
void expect_consistent(const SurfaceMesh& mesh, const TriangleTree::Hit& hit,
                       const Eigen::Vector3d& p, double scale) {
  ASSERT_GE(hit.triangle, 0);
  ASSERT_LT(hit.triangle, mesh.F.rows());
  const Eigen::Vector3d& w = hit.where.weights;
  EXPECT_GE(w.minCoeff(), 0.0);
  EXPECT_NEAR(w.sum(), 1.0, 1e-15);
  const int region = hit.where.region;
  for (int k = 0; k < 3; ++k) {
    const int kind = feature_kind(region);
    const bool zero = kind == 0 ? k != region : (kind == 1 && k == (region - kEdgeAB + 2) % 3);
    if (zero) {
      EXPECT_EQ(w(k), 0.0) << "region " << region;
    } else {
      EXPECT_GT(w(k), 0.0) << "region " << region;
    }
  }
  Eigen::Vector3d from_weights = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    from_weights += w(k) * mesh.V.row(mesh.F(hit.triangle, k)).transpose();
  EXPECT_LT((from_weights - hit.where.point).norm(), 1e-15 * scale);
  EXPECT_DOUBLE_EQ(hit.distance2, (p - hit.where.point).squaredNorm());
}

// Random queries in the box [−half, half] against the exhaustive scan; counts
// in `kinds` how many hits fell in each kind of feature (corner, edge, face).
void expect_matches_scan(const TriangleTree& tree, const SurfaceMesh& mesh,
                         const Eigen::Vector3d& half, int n, std::uint64_t salt,
                         std::array<int, 3>& kinds) {
  auto rng = test::make_rng(salt);
  const double scale = half.norm();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = uniform_point(rng, half);
    const TriangleTree::Hit hit = tree.closest(p);
    const TriangleTree::Hit scan = scan_closest(mesh, p);
    ASSERT_NEAR(std::sqrt(hit.distance2), std::sqrt(scan.distance2), 1e-15 * scale)
        << p.transpose();
    expect_consistent(mesh, hit, p, scale);
    ++kinds[static_cast<std::size_t>(feature_kind(hit.where.region))];
  }
}

// Two wavy square sheets 0.2 mm apart (200 triangles each): boxes that
// overlap almost everywhere, the hard case of a bounding-volume hierarchy.
SurfaceMesh thin_sheet() {
  const SurfaceMesh one = test::square_grid(10, 0.1);
  const auto nv = one.V.rows();
  SurfaceMesh two;
  two.V.resize(2 * nv, 3);
  two.F.resize(2 * one.F.rows(), 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    Eigen::Vector3d x = one.V.row(v);
    x.z() = 1e-4 * std::sin(60.0 * x.x()) * std::cos(40.0 * x.y());
    two.V.row(v) = x;
    two.V.row(nv + v) = x - Eigen::Vector3d(0.0, 0.0, 2e-4);
  }
  two.F.topRows(one.F.rows()) = one.F;
  two.F.bottomRows(one.F.rows()) = one.F.array() + static_cast<int>(nv);
  return two;
}

TEST(TriangleTree, MatchesAnExhaustiveScanOnAnIcosphere) {
  const SurfaceMesh sphere = test::icosphere(2, 0.05);  // 320 triangles
  const TriangleTree tree(sphere.V, sphere.F);
  EXPECT_EQ(tree.size(), sphere.F.rows());
  std::array<int, 3> kinds{0, 0, 0};
  expect_matches_scan(tree, sphere, Eigen::Vector3d::Constant(0.08), 600, 1, kinds);
  // Points all around a convex surface land on corners, edges and faces.
  for (int k = 0; k < 3; ++k) EXPECT_GT(kinds[static_cast<std::size_t>(k)], 0) << k;
  // The root box is the mesh's.
  EXPECT_EQ(tree.lo(), Eigen::Vector3d(sphere.V.colwise().minCoeff()));
  EXPECT_EQ(tree.hi(), Eigen::Vector3d(sphere.V.colwise().maxCoeff()));
}

TEST(TriangleTree, MatchesAnExhaustiveScanOnAThinSheet) {
  const SurfaceMesh sheet = thin_sheet();
  const TriangleTree tree(sheet.V, sheet.F);
  // Close to the sheet (between and around its layers) and farther away.
  std::array<int, 3> near{0, 0, 0};
  expect_matches_scan(tree, sheet, Eigen::Vector3d(0.06, 0.06, 5e-4), 500, 2, near);
  EXPECT_GT(near[2], 0);  // points over the interior land on faces
  std::array<int, 3> far{0, 0, 0};
  expect_matches_scan(tree, sheet, Eigen::Vector3d(0.08, 0.08, 0.03), 200, 3, far);
  EXPECT_GT(far[1], 0);  // points beyond the border land on edges
}

TEST(TriangleTree, TiesGoToTheLowestTriangleIndex) {
  // A flat grid with dyadic coordinates: the distances are exact, so every
  // triangle around a vertex (or on both sides of an edge) ties exactly.
  const int n = 8;
  const SurfaceMesh grid = test::square_grid(n, 1.0);
  const TriangleTree tree(grid.V, grid.F);
  const Eigen::Vector3d up(0.0, 0.0, 0.25);
  int ties = 0;
  for (int j = 1; j < n; ++j) {
    for (int i = 1; i < n; ++i) {
      const int v = j * (n + 1) + i;
      const int u = v + 1;  // its neighbour along x
      // Above the vertex, and above the midpoint of the edge v–u.
      for (const bool on_edge : {false, true}) {
        const Eigen::Vector3d below =
            on_edge ? Eigen::Vector3d(0.5 * (grid.V.row(v) + grid.V.row(u))) : grid.V.row(v);
        const Eigen::Vector3d p = below + up;
        int lowest = -1;
        int tied = 0;
        for (int f = 0; f < static_cast<int>(grid.F.rows()); ++f) {
          const auto holds = [&](int w) { return (grid.F.row(f).array() == w).any(); };
          if (holds(v) && (!on_edge || holds(u))) {
            if (lowest < 0) lowest = f;
            ++tied;
          }
        }
        ASSERT_GE(tied, 2);
        const TriangleTree::Hit hit = tree.closest(p);
        EXPECT_EQ(hit.distance2, 0.0625);
        EXPECT_EQ(hit.triangle, lowest) << "vertex " << v << (on_edge ? " edge" : "");
        EXPECT_EQ(feature_kind(hit.where.region), on_edge ? 1 : 0);
        ++ties;
      }
    }
  }
  EXPECT_EQ(ties, 2 * (n - 1) * (n - 1));
}

TEST(TriangleTree, RefitAnswersAsARebuild) {
  const SurfaceMesh sphere = test::icosphere(3, 0.05);
  TriangleTree refitted(sphere.V, sphere.F);
  // A large, uneven motion: squash along z, wobble in x.
  SurfaceMesh moved = sphere;
  for (Eigen::Index v = 0; v < moved.V.rows(); ++v) {
    moved.V(v, 2) *= 0.6;
    moved.V(v, 0) += 0.01 * std::sin(60.0 * moved.V(v, 1));
  }
  refitted.refit(moved.V);
  const TriangleTree rebuilt(moved.V, moved.F);
  EXPECT_EQ(refitted.lo(), rebuilt.lo());
  EXPECT_EQ(refitted.hi(), rebuilt.hi());
  auto rng = test::make_rng(4);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d p = uniform_point(rng, Eigen::Vector3d::Constant(0.07));
    const TriangleTree::Hit a = refitted.closest(p);
    const TriangleTree::Hit b = rebuilt.closest(p);
    ASSERT_EQ(a.triangle, b.triangle) << p.transpose();
    EXPECT_EQ(a.distance2, b.distance2);
    EXPECT_EQ(a.where.point, b.where.point);
    EXPECT_EQ(a.where.weights, b.where.weights);
    EXPECT_EQ(a.where.region, b.where.region);
  }
  std::array<int, 3> kinds{0, 0, 0};
  expect_matches_scan(refitted, moved, Eigen::Vector3d::Constant(0.07), 100, 5, kinds);
  // Back to the rest shape: the answers of the first build.
  refitted.refit(sphere.V);
  const TriangleTree original(sphere.V, sphere.F);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p = uniform_point(rng, Eigen::Vector3d::Constant(0.07));
    EXPECT_EQ(refitted.closest(p).triangle, original.closest(p).triangle);
    EXPECT_EQ(refitted.closest(p).distance2, original.closest(p).distance2);
  }
}

TEST(TriangleTree, ConcurrentQueriesAnswerAsSerialOnes) {
  const SurfaceMesh sheet = thin_sheet();
  const TriangleTree tree(sheet.V, sheet.F);
  auto rng = test::make_rng(6);
  constexpr int kPoints = 4000;
  std::vector<Eigen::Vector3d> points(kPoints);
  for (auto& p : points) p = uniform_point(rng, Eigen::Vector3d(0.06, 0.06, 1e-3));
  std::vector<TriangleTree::Hit> serial(kPoints);
  for (int i = 0; i < kPoints; ++i)
    serial[static_cast<std::size_t>(i)] = tree.closest(points[static_cast<std::size_t>(i)]);
  std::vector<TriangleTree::Hit> parallel(kPoints);
  const auto half = [&](int begin, int end) {
    for (int i = begin; i < end; ++i)
      parallel[static_cast<std::size_t>(i)] = tree.closest(points[static_cast<std::size_t>(i)]);
  };
  std::thread other(half, 0, kPoints / 2);
  half(kPoints / 2, kPoints);
  other.join();
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(parallel[i].triangle, serial[i].triangle);
    EXPECT_EQ(parallel[i].distance2, serial[i].distance2);
  }
}

TEST(TriangleTree, EmptyTreeFindsNothing) {
  const Eigen::Vector3d p(0.1, 0.2, 0.3);
  for (const TriangleTree& tree :
       {TriangleTree(), TriangleTree(Eigen::MatrixX3d(0, 3), Eigen::MatrixX3i(0, 3))}) {
    EXPECT_EQ(tree.size(), 0);
    const TriangleTree::Hit hit = tree.closest(p);
    EXPECT_EQ(hit.triangle, -1);
    EXPECT_EQ(hit.distance2, std::numeric_limits<double>::infinity());
    EXPECT_TRUE((tree.lo().array() > tree.hi().array()).all());
  }
  // A non-finite query finds nothing either.
  const SurfaceMesh sphere = test::icosphere(1, 0.05);
  const TriangleTree tree(sphere.V, sphere.F);
  EXPECT_EQ(tree.closest(Eigen::Vector3d(std::nan(""), 0.0, 0.0)).triangle, -1);
}

}  // namespace
}  // namespace palpa::geometry
