// SPDX-License-Identifier: AGPL-3.0-or-later
// Benchmarks of the contact module. Prints one JSON line per figure (see
// BENCHMARKS.md), each with its in-run reference and the ratio.
//
//  1. Closest-point queries per second (1 thread, with the inside test and the
//     closest feature) against tori of ~2k and ~50k triangles, for 10k points in
//     the bounding box and 10k points within 1 mm of the surface: palpa's own
//     BVH; reference: CGAL's AABB_tree (with its distance-query accelerator).
//     Accuracy: largest distance difference between the two.
//  2. Tree build time: own BVH vs CGAL's AABB_tree; and the whole Obstacle
//     construction (validation, normals, tree).
//  3. A deforming obstacle (a body surface moving each Newton step): time of
//     set_vertices() with refit, with rebuild, and with CGAL's rebuild, and the
//     query rate after the refit relative to a fresh build (tree quality).
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
#include "contact/shapes.hpp"
#include "palpa/contact/contact.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/contact/detail/bvh.hpp"
#include "palpa/contact/detail/cgal_tree.hpp"

namespace {

using palpa::bench::emit;
using palpa::bench::median_seconds;
using palpa::bench::throughput;
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

double queries_per_second(const contact::Obstacle& o, const Eigen::Matrix3Xd& points) {
  double sink = 0.0;
  const double rate = throughput(
      [&] {
        for (Eigen::Index i = 0; i < points.cols(); ++i)
          sink += o.closest_point(points.col(i)).distance;
      },
      static_cast<double>(points.cols()));
  if (sink < 0.0) fmt::print("");  // keep the loop
  return rate;
}

double max_distance_difference(const contact::Obstacle& a, const contact::Obstacle& b,
                               const Eigen::Matrix3Xd& points) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    worst = std::max(worst, std::abs(a.closest_point(points.col(i)).distance -
                                     b.closest_point(points.col(i)).distance));
  }
  return worst;
}

void bench_mesh(const MeshCase& mc) {
  const palpa::SurfaceMesh mesh = palpa::test::torus_mesh(kRingRadius, kTubeRadius, mc.nu, mc.nv);
  const auto triangles = static_cast<long>(mesh.F.rows());
  contact::ObstacleOptions cgal_options;
  cgal_options.tree = contact::TreeKind::Cgal;
  const contact::Obstacle own(mesh, mc.name);
  const contact::Obstacle cgal(mesh, mc.name, cgal_options);
  std::mt19937_64 rng(20261129);  // fixed: the same points every run

  // 1. Queries.
  for (const auto& [where, points] :
       {std::pair<std::string, Eigen::Matrix3Xd>{"bounding box", box_points(rng)},
        std::pair<std::string, Eigen::Matrix3Xd>{"within 1 mm of the surface", near_points(rng)}}) {
    const double rate_own = queries_per_second(own, points);
    const double rate_cgal = queries_per_second(cgal, points);
    emit({{"bench", "contact.closest_point"},
          {"mesh", mc.name},
          {"triangles", triangles},
          {"points", where},
          {"figure", "closest point + feature + inside test per second (1 thread), own BVH"},
          {"queries_per_s", rate_own},
          {"reference", "CGAL AABB_tree (accelerated distance queries)"},
          {"reference_queries_per_s", rate_cgal},
          {"ratio_to_reference", rate_own / rate_cgal},
          {"accuracy_max_distance_difference_m", max_distance_difference(own, cgal, points)}});
  }

  // 2. Build.
  palpa::contact::detail::Bvh bvh;
  const double t_own = median_seconds([] {}, [&] { bvh.build(mesh.V, mesh.F); });
  const double t_cgal =
      median_seconds([] {}, [&] { palpa::contact::detail::CgalTree tree(mesh.V, mesh.F); });
  const double t_obstacle = median_seconds([] {}, [&] { contact::Obstacle o(mesh, mc.name); });
  emit({{"bench", "contact.tree_build"},
        {"mesh", mc.name},
        {"triangles", triangles},
        {"figure", "tree build time, own BVH"},
        {"seconds", t_own},
        {"reference", "CGAL AABB_tree build + accelerate_distance_queries"},
        {"reference_seconds", t_cgal},
        {"ratio_to_reference", t_own / t_cgal},
        {"obstacle_construction_seconds", t_obstacle},
        {"obstacle_construction_note", "validation (with the exact self-intersection test) + normals + own tree"}});

  // 3. Deformation: every vertex moves (a squash plus a wobble of ~5 mm).
  palpa::SurfaceMesh moved = mesh;
  for (Eigen::Index v = 0; v < moved.V.rows(); ++v) {
    moved.V(v, 2) *= 0.8;
    moved.V(v, 0) += 0.005 * std::sin(40.0 * moved.V(v, 1));
  }
  contact::Obstacle refit(mesh, mc.name);
  contact::Obstacle rebuild(mesh, mc.name);
  contact::Obstacle cgal_rebuild(mesh, mc.name, cgal_options);
  bool flip = false;
  auto next = [&] {
    flip = !flip;
    return flip ? moved.V : mesh.V;
  };
  const double t_refit = median_seconds([] {}, [&] { refit.set_vertices(next(), true); });
  const double t_rebuild = median_seconds([] {}, [&] { rebuild.set_vertices(next(), false); });
  const double t_cgal_rebuild = median_seconds([] {}, [&] { cgal_rebuild.set_vertices(next()); });
  const double t_box_refit = median_seconds([] {}, [&] { bvh.refit(next(), mesh.F); });
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
        {"reference", "set_vertices() with a rebuild of the own BVH"},
        {"reference_seconds", t_rebuild},
        {"ratio_to_reference", t_refit / t_rebuild},
        {"cgal_rebuild_seconds", t_cgal_rebuild},
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
