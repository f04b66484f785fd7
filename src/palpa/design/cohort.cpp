// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/cohort.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "palpa/core/error.hpp"

namespace palpa::design {

double cohort_value(const CohortObjective& o, const Eigen::VectorXd& r, Eigen::VectorXd* weights) {
  const Eigen::Index n = r.size();
  if (n == 0) throw Error(ErrorKind::Input, "a cohort objective needs at least one body");
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  double J = 0.0;
  switch (o.aggregate) {
    case CohortAggregate::Mean:
      J = r.mean();
      w.setConstant(1.0 / static_cast<double>(n));
      break;
    case CohortAggregate::Quantile: {
      if (!(o.quantile >= 0.0 && o.quantile < 1.0)) {
        throw Error(ErrorKind::Input, fmt::format("the cohort's quantile must be in [0, 1), got {}", o.quantile));
      }
      // The worst first; ties in the bodies' order, so J's weights are
      // reproducible.
      std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
      std::iota(order.begin(), order.end(), Eigen::Index{0});
      std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return r[a] > r[b]; });
      const double m = std::max(1.0, (1.0 - o.quantile) * static_cast<double>(n));
      double left = m;
      for (Eigen::Index i : order) {
        const double take = std::min(1.0, left);
        if (take <= 0.0) break;
        w[i] = take / m;
        J += w[i] * r[i];
        left -= take;
      }
      break;
    }
    case CohortAggregate::SmoothMax: {
      const double tau = o.sharpness;
      if (!(tau > 0.0) || !std::isfinite(tau)) {
        throw Error(ErrorKind::Input, fmt::format("the cohort's smooth-max sharpness τ must be finite and > 0, got {}", tau));
      }
      const double top = r.maxCoeff();
      const Eigen::VectorXd e = ((r.array() - top) / tau).exp();
      const double sum = e.sum();
      J = top + tau * std::log(sum / static_cast<double>(n));
      w = e / sum;
      break;
    }
  }
  if (weights != nullptr) *weights = w;
  return J;
}

std::string to_string(CohortAggregate a) {
  switch (a) {
    case CohortAggregate::Mean:
      return "mean";
    case CohortAggregate::Quantile:
      return "quantile";
    case CohortAggregate::SmoothMax:
      return "max";
  }
  return "mean";
}

CohortAggregate parse_cohort_aggregate(const std::string& name, const std::string& context) {
  for (CohortAggregate a : {CohortAggregate::Mean, CohortAggregate::Quantile, CohortAggregate::SmoothMax}) {
    if (name == to_string(a)) return a;
  }
  throw Error(ErrorKind::Input, fmt::format("{}: unknown cohort objective '{}'", context, name), {},
              "\"mean\", \"quantile\" or \"max\"");
}

}  // namespace palpa::design
