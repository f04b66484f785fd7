// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmarks of the contact module. Prints one JSON line per figure (see
// BENCHMARKS.md), each with its in-run reference and the ratio.
//
//  1. Closest-point queries per second (1 thread) against tori of ~2k and ~50k
//     triangles, for 10k points in the bounding box and 10k points within 1 mm
//     of the surface: palpa's geometry::TriangleTree; reference: CGAL's
//     AABB_tree (with its distance-query accelerator, the tests' reference
//     tree). Also the rate of Obstacle::closest_point (the tree query plus the
//     closest feature and the inside test). Accuracy: largest distance
//     difference between the two trees.
//  2. Tree build time: TriangleTree vs CGAL's AABB_tree; and the whole Obstacle
//     construction (validation, normals, tree).
//  3. A deforming obstacle (a body surface moving each Newton step): time of
//     set_vertices() with refit and with rebuild, of the box refit alone and of
//     a CGAL tree rebuilt on the moved vertices, and the query rate after the
//     refit relative to a fresh build (tree quality).
//  4. Batch detection of 10k points (PenaltyContact::commit, TBB) and
//     PenaltyContact::detected_energy(), against the same queries in a 1-thread loop.
//
// Options: --quick uses the 2k mesh only.

#include <fmt/format.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "common/cgal_triangle_tree.hpp"
#include "contact/shapes.hpp"
#include "palpa/contact/contact.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/geometry/triangle_tree.hpp"

namespace {

using palpa::bench::emit;
using palpa::bench::median_seconds;
using palpa::bench::throughput;
using palpa::geometry::TriangleTree;
using palpa::test::CgalTriangleTree;
namespace contact = palpa::contact;

constexpr int kQueries = 10000;
constexpr double kTubeRadius = 0.05;  // m
constexpr double kRingRadius = 0.15;  // m
constexpr double kNearBand = 1e-3;    // m: "near the surface"

struct MeshCase {
  std::string name;
  int nu, nv;  // torus resolution: 2·nu·nv triangles
};

// 10k points uniformly in the (slightly enlarged) bounding box.
Eigen::Matrix3Xd box_points(std::mt19937_64& rng) {
  const double xy = kRingRadius + kTubeRadius * 1.1;
  const double z = kTubeRadius * 1.1;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd p(3, kQueries);
  for (int i = 0; i < kQueries; ++i) {
    const double ux = u(rng), uy = u(rng), uz = u(rng);  // drawn in order on every compiler
    p.col(i) = Eigen::Vector3d(xy * ux, xy * uy, z * uz);
  }
  return p;
}

// 10k points within kNearBand of the smooth torus (half inside).
Eigen::Matrix3Xd near_points(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> band(-kNearBand, kNearBand);
  Eigen::Matrix3Xd p(3, kQueries);
  for (int i = 0; i < kQueries; ++i) {
    const double u = angle(rng);
    const double w = angle(rng);
    const double r = kTubeRadius + band(rng);
    p.col(i) = Eigen::Vector3d((kRingRadius + r * std::cos(w)) * std::cos(u),
                               (kRingRadius + r * std::cos(w)) * std::sin(u), r * std::sin(w));
  }
  return p;
}

// Queries per second of distance(point) (1 thread) over the points.
template <class Distance>
double queries_per_second(const Distance& distance, const Eigen::Matrix3Xd& points) {
  double sink = 0.0;
  const double rate = throughput(
      [&] {
        for (Eigen::Index i = 0; i < points.cols(); ++i) sink += distance(points.col(i));
      },
      static_cast<double>(points.cols()));
  if (sink < 0.0) fmt::print("");  // keep the loop
  return rate;
}

double queries_per_second(const contact::Obstacle& o, const Eigen::Matrix3Xd& points) {
  return queries_per_second([&](const Eigen::Vector3d& p) { return o.closest_point(p).distance; },
                            points);
}

double max_distance_difference(const TriangleTree& a, const CgalTriangleTree& b,
                               const Eigen::Matrix3Xd& points) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    worst = std::max(worst, std::abs(std::sqrt(a.closest(points.col(i)).distance2) -
                                     std::sqrt(b.closest(points.col(i)).distance2)));
  }
  return worst;
}

void bench_mesh(const MeshCase& mc) {
  const palpa::SurfaceMesh mesh = palpa::test::torus_mesh(kRingRadius, kTubeRadius, mc.nu, mc.nv);
  const auto triangles = static_cast<long>(mesh.F.rows());
  const contact::Obstacle obstacle(mesh, mc.name);
  const TriangleTree own(mesh.V, mesh.F);
  const CgalTriangleTree cgal(mesh.V, mesh.F);
  std::mt19937_64 rng(20261129);  // fixed: the same points every run

  // 1. Queries.
  for (const auto& [where, points] :
       {std::pair<std::string, Eigen::Matrix3Xd>{"bounding box", box_points(rng)},
        std::pair<std::string, Eigen::Matrix3Xd>{"within 1 mm of the surface", near_points(rng)}}) {
    const double rate_own = queries_per_second(
        [&](const Eigen::Vector3d& p) { return own.closest(p).distance2; }, points);
    const double rate_cgal = queries_per_second(
        [&](const Eigen::Vector3d& p) { return cgal.closest(p).distance2; }, points);
    emit({{"bench", "contact.closest_point"},
          {"mesh", mc.name},
          {"triangles", triangles},
          {"points", where},
          {"figure", "closest point per second (1 thread), geometry::TriangleTree"},
          {"queries_per_s", rate_own},
          {"reference", "CGAL AABB_tree (accelerated distance queries)"},
          {"reference_queries_per_s", rate_cgal},
          {"ratio_to_reference", rate_own / rate_cgal},
          {"obstacle_queries_per_s", queries_per_second(obstacle, points)},
          {"obstacle_note",
           "Obstacle::closest_point: the tree query + closest feature + inside test"},
          {"accuracy_max_distance_difference_m", max_distance_difference(own, cgal, points)}});
  }

  // 2. Build.
  TriangleTree tree;
  const double t_own = median_seconds([] {}, [&] { tree.build(mesh.V, mesh.F); });
  const double t_cgal = median_seconds([] {}, [&] { CgalTriangleTree reference(mesh.V, mesh.F); });
  const double t_obstacle = median_seconds([] {}, [&] { contact::Obstacle o(mesh, mc.name); });
  emit({{"bench", "contact.tree_build"},
        {"mesh", mc.name},
        {"triangles", triangles},
        {"figure", "tree build time, geometry::TriangleTree"},
        {"seconds", t_own},
        {"reference", "CGAL AABB_tree build + accelerate_distance_queries"},
        {"reference_seconds", t_cgal},
        {"ratio_to_reference", t_own / t_cgal},
        {"obstacle_construction_seconds", t_obstacle},
        {"obstacle_construction_note",
         "validation (with the exact self-intersection test) + normals + tree"}});

  // 3. Deformation: every vertex moves (a squash plus a wobble of ~5 mm).
  palpa::SurfaceMesh moved = mesh;
  for (Eigen::Index v = 0; v < moved.V.rows(); ++v) {
    moved.V(v, 2) *= 0.8;
    moved.V(v, 0) += 0.005 * std::sin(40.0 * moved.V(v, 1));
  }
  contact::Obstacle refit(mesh, mc.name);
  contact::Obstacle rebuild(mesh, mc.name);
  bool flip = false;
  auto next = [&] {
    flip = !flip;
    return flip ? moved.V : mesh.V;
  };
  const double t_refit = median_seconds([] {}, [&] { refit.set_vertices(next(), true); });
  const double t_rebuild = median_seconds([] {}, [&] { rebuild.set_vertices(next(), false); });
  const double t_cgal_rebuild =
      median_seconds([] {}, [&] { CgalTriangleTree reference(next(), mesh.F); });
  const double t_box_refit = median_seconds([] {}, [&] { tree.refit(next()); });
  refit.set_vertices(moved.V, true);
  rebuild.set_vertices(moved.V, false);
  const Eigen::Matrix3Xd pts = near_points(rng);
  const double q_refit = queries_per_second(refit, pts);
  const double q_rebuild = queries_per_second(rebuild, pts);
  emit({{"bench", "contact.deforming_obstacle"},
        {"mesh", mc.name},
        {"triangles", triangles},
        {"figure", "set_vertices() with refit (normals + box refit)"},
        {"seconds", t_refit},
        {"reference", "set_vertices() with a rebuild of the tree"},
        {"reference_seconds", t_rebuild},
        {"ratio_to_reference", t_refit / t_rebuild},
        {"cgal_tree_rebuild_seconds", t_cgal_rebuild},
        {"box_refit_only_seconds", t_box_refit},
        {"query_rate_after_refit_over_fresh_build", q_refit / q_rebuild}});

  // 4. Batch detection (near points: ~half penetrate).
  std::vector<int> which(static_cast<std::size_t>(pts.cols()));
  for (std::size_t i = 0; i < which.size(); ++i) which[i] = static_cast<int>(i);
  contact::PenaltyContact potential(contact::vertex_samples(which), 1e4, mc.name);
  const double t_detect = median_seconds([] {}, [&] { potential.commit(refit, pts); });
  double energy = 0.0;
  const double t_energy = median_seconds([] {}, [&] { energy = potential.detected_energy(refit, pts); });
  const double t_serial = median_seconds([] {},
                                         [&] {
                                           contact::ClosestPoint c;
                                           for (int i : which)
                                             (void)refit.penetration(pts.col(i), c);
                                         });
  emit({{"bench", "contact.batch_detection"},
        {"mesh", mc.name},
        {"triangles", triangles},
        {"points", kQueries},
        {"contacts", static_cast<long>(potential.size())},
        {"figure", "PenaltyContact::commit (TBB)"},
        {"seconds", t_detect},
        {"detected_energy_seconds", t_energy},
        {"reference", "the same queries in one thread"},
        {"reference_seconds", t_serial},
        {"ratio_to_reference", t_detect / t_serial},
        {"energy_J", energy}});
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::vector<MeshCase> cases = {{"torus-2k", 40, 25}};
  if (!quick) cases.push_back({"torus-50k", 250, 100});
  for (const auto& mc : cases) bench_mesh(mc);
  return 0;
}
