// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Pearson's correlation of two equally long samples.

#include <cmath>
#include <cstddef>
#include <numeric>
#include <span>

namespace palpa {

// r in [−1, 1]; 0 when either sample is constant (no correlation defined).
inline double pearson(std::span<const double> a, std::span<const double> b) {
  const double n = static_cast<double>(a.size());
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n;
  const double mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0.0 && sbb > 0.0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

}  // namespace palpa
