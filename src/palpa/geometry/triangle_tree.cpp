// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/triangle_tree.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace palpa::geometry {

namespace {

// Squared distance from p to the box [lo, hi] (0 inside).
double box_distance2(const Eigen::Vector3d& p, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

// Entries of a query's node stack. Median splits keep the depth at most
// ⌈log2 #F⌉ + 1 (< 33 for any int count), and a depth-first search holds at
// most depth + 1 pending nodes.
constexpr int kTreeStackSize = 64;

}  // namespace

TriangleTree::TriangleTree() {
  nodes_.push_back({Eigen::Vector3d::Constant(1.0), Eigen::Vector3d::Constant(-1.0), 0, 0});
}

TriangleTree::TriangleTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  build(V, F);
}

void TriangleTree::build(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const auto nf = static_cast<int>(F.rows());
  order_.resize(static_cast<std::size_t>(nf));
  std::iota(order_.begin(), order_.end(), 0);
  max_vertex_ = nf == 0 ? -1 : F.maxCoeff();
  assert(nf == 0 || (F.minCoeff() >= 0 && max_vertex_ < V.rows()));
  std::vector<Eigen::Vector3d> centroid(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    centroid[static_cast<std::size_t>(f)] =
        (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
  }
  nodes_.clear();
  nodes_.reserve(static_cast<std::size_t>(2 * nf / kLeafSize + 2));
  if (nf == 0) {
    vertices_.clear();
    corner_.clear();
    nodes_.push_back({Eigen::Vector3d::Constant(1.0), Eigen::Vector3d::Constant(-1.0), 0, 0});
    return;
  }
  build_node(0, nf, centroid);
  vertices_.resize(order_.size());
  for (std::size_t s = 0; s < order_.size(); ++s)
    vertices_[s] = {F(order_[s], 0), F(order_[s], 1), F(order_[s], 2)};
  refit(V);
}

int TriangleTree::build_node(int begin, int end, const std::vector<Eigen::Vector3d>& centroid) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int s = begin; s < end; ++s) {
    const auto& c = centroid[static_cast<std::size_t>(order_[static_cast<std::size_t>(s)])];
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) {
                     return centroid[static_cast<std::size_t>(a)][axis] <
                            centroid[static_cast<std::size_t>(b)][axis];
                   });
  build_node(begin, mid, centroid);
  const int right = build_node(mid, end, centroid);
  nodes_[static_cast<std::size_t>(index)].first = right;
  nodes_[static_cast<std::size_t>(index)].count = 0;
  return index;
}

void TriangleTree::store_corners(const Eigen::MatrixX3d& V) {
  corner_.resize(3 * vertices_.size());
  for (std::size_t s = 0; s < vertices_.size(); ++s) {
    for (std::size_t k = 0; k < 3; ++k) corner_[3 * s + k] = V.row(vertices_[s][k]);
  }
}

void TriangleTree::refit(const Eigen::MatrixX3d& V) {
  if (order_.empty()) return;
  assert(max_vertex_ < V.rows());
  store_corners(V);
  // Children follow their parent in the array: one backward sweep sees every
  // child before its parent.
  for (auto i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    Node& n = nodes_[static_cast<std::size_t>(i)];
    if (n.count > 0) {
      n.lo = corner_[3 * static_cast<std::size_t>(n.first)];
      n.hi = n.lo;
      for (int s = 3 * n.first; s < 3 * (n.first + n.count); ++s) {
        n.lo = n.lo.cwiseMin(corner_[static_cast<std::size_t>(s)]);
        n.hi = n.hi.cwiseMax(corner_[static_cast<std::size_t>(s)]);
      }
    } else {
      const Node& l = nodes_[static_cast<std::size_t>(i + 1)];
      const Node& r = nodes_[static_cast<std::size_t>(n.first)];
      n.lo = l.lo.cwiseMin(r.lo);
      n.hi = l.hi.cwiseMax(r.hi);
    }
  }
}

TriangleTree::Hit TriangleTree::closest(const Eigen::Vector3d& p) const {
  Hit best;
  if (order_.empty()) return best;
  std::array<int, kTreeStackSize> stack{};
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = 0;
  // A box at exactly the best distance is still visited (> rather than ≥), so
  // that a tie with a lower triangle index in it is found.
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[static_cast<std::size_t>(--top)])];
    if (box_distance2(p, n.lo, n.hi) > best.distance2) continue;
    if (n.count > 0) {
      for (int s = n.first; s < n.first + n.count; ++s) {
        const auto c = 3 * static_cast<std::size_t>(s);
        const TrianglePoint tp = closest_on_triangle(p, corner_[c], corner_[c + 1], corner_[c + 2]);
        const double d2 = (p - tp.point).squaredNorm();
        const int triangle = order_[static_cast<std::size_t>(s)];
        if (d2 < best.distance2 || (d2 == best.distance2 && triangle < best.triangle)) {
          best.distance2 = d2;
          best.triangle = triangle;
          best.where = tp;
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last).
    const int left = static_cast<int>(&n - nodes_.data()) + 1;
    const int right = n.first;
    const double dl = box_distance2(p, nodes_[static_cast<std::size_t>(left)].lo,
                                    nodes_[static_cast<std::size_t>(left)].hi);
    const double dr = box_distance2(p, nodes_[static_cast<std::size_t>(right)].lo,
                                    nodes_[static_cast<std::size_t>(right)].hi);
    const bool left_first = dl <= dr;
    const int near = left_first ? left : right;
    const int far = left_first ? right : left;
    assert(top + 2 <= kTreeStackSize);
    if ((left_first ? dr : dl) <= best.distance2) stack[static_cast<std::size_t>(top++)] = far;
    if ((left_first ? dl : dr) <= best.distance2) stack[static_cast<std::size_t>(top++)] = near;
  }
  return best;
}

}  // namespace palpa::geometry
