// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/submesh.hpp"

namespace palpa::geometry {

Submesh submesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  Submesh s;
  s.to_new.assign(static_cast<std::size_t>(V.rows()), -1);
  s.mesh.F.resize(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      int& i = s.to_new[static_cast<std::size_t>(F(f, c))];
      if (i < 0) {
        i = static_cast<int>(s.to_old.size());
        s.to_old.push_back(F(f, c));
      }
      s.mesh.F(f, c) = i;
    }
  }
  s.mesh.V.resize(static_cast<Eigen::Index>(s.to_old.size()), 3);
  for (std::size_t i = 0; i < s.to_old.size(); ++i) {
    s.mesh.V.row(static_cast<Eigen::Index>(i)) = V.row(s.to_old[i]);
  }
  return s;
}

}  // namespace palpa::geometry
