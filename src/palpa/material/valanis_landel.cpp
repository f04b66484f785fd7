// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/valanis_landel.hpp"

namespace palpa::material {

Scalar3 ValanisLandelMaterial::part(Part p, double x) const {
  if (needs_continuation(p) && x < kContinuationThreshold) {
    return quadratic_continuation(raw_part(p, kContinuationThreshold), kContinuationThreshold, x);
  }
  return raw_part(p, x);
}

void ValanisLandelMaterial::evaluate(const Vec3& l, EvalOrder order, StretchEnergy& out) const {
  const bool with_g = has_part(Part::G);
  const bool with_h = has_part(Part::H);
  const double jac = l[0] * l[1] * l[2];
  // Pair (i, j) for each "other two" index: pair products λiλj.
  const Scalar3 f0 = part(Part::F, l[0]);
  const Scalar3 f1 = part(Part::F, l[1]);
  const Scalar3 f2 = part(Part::F, l[2]);
  Scalar3 g01;
  Scalar3 g02;
  Scalar3 g12;
  if (with_g) {
    g01 = part(Part::G, l[0] * l[1]);
    g02 = part(Part::G, l[0] * l[2]);
    g12 = part(Part::G, l[1] * l[2]);
  }
  const Scalar3 hh = with_h ? part(Part::H, jac) : Scalar3{};

  out.psi = f0.v + f1.v + f2.v + g01.v + g02.v + g12.v + hh.v;
  if (order == EvalOrder::Energy) return;

  const double c12 = l[1] * l[2];  // ∂J/∂λ0
  const double c02 = l[0] * l[2];  // ∂J/∂λ1
  const double c01 = l[0] * l[1];  // ∂J/∂λ2
  out.grad[0] = f0.d1 + l[1] * g01.d1 + l[2] * g02.d1 + c12 * hh.d1;
  out.grad[1] = f1.d1 + l[0] * g01.d1 + l[2] * g12.d1 + c02 * hh.d1;
  out.grad[2] = f2.d1 + l[0] * g02.d1 + l[1] * g12.d1 + c01 * hh.d1;
  if (order == EvalOrder::Gradient) return;

  Mat3& H = out.hess;
  H(0, 0) = f0.d2 + l[1] * l[1] * g01.d2 + l[2] * l[2] * g02.d2 + c12 * c12 * hh.d2;
  H(1, 1) = f1.d2 + l[0] * l[0] * g01.d2 + l[2] * l[2] * g12.d2 + c02 * c02 * hh.d2;
  H(2, 2) = f2.d2 + l[0] * l[0] * g02.d2 + l[1] * l[1] * g12.d2 + c01 * c01 * hh.d2;
  H(0, 1) = g01.d1 + c01 * g01.d2 + l[2] * hh.d1 + c12 * c02 * hh.d2;
  H(0, 2) = g02.d1 + c02 * g02.d2 + l[1] * hh.d1 + c12 * c01 * hh.d2;
  H(1, 2) = g12.d1 + c12 * g12.d2 + l[0] * hh.d1 + c02 * c01 * hh.d2;
  H(1, 0) = H(0, 1);
  H(2, 0) = H(0, 2);
  H(2, 1) = H(1, 2);
}

void ValanisLandelMaterial::add_part_dparam(Part p, double x, double w,
                                            Eigen::Ref<Eigen::MatrixXd> out,
                                            Eigen::Index row) const {
  if (needs_continuation(p) && x < kContinuationThreshold) {
    // d/dθ of [raw′(x0) + raw″(x0) (x - x0)]
    accumulate_part_dparam(p, kContinuationThreshold, w, w * (x - kContinuationThreshold), out,
                           row);
  } else {
    accumulate_part_dparam(p, x, w, 0.0, out, row);
  }
}

void ValanisLandelMaterial::d2psi_dlambda_dparam(const Vec3& l,
                                                 Eigen::Ref<Eigen::MatrixXd> out) const {
  out.setZero();
  const bool with_g = has_part(Part::G);
  const bool with_h = has_part(Part::H);
  const double jac = l[0] * l[1] * l[2];
  for (Eigen::Index i = 0; i < 3; ++i) {
    const Eigen::Index j = (i + 1) % 3;
    const Eigen::Index k = (i + 2) % 3;
    add_part_dparam(Part::F, l[i], 1.0, out, i);
    if (with_g) {
      add_part_dparam(Part::G, l[i] * l[j], l[j], out, i);
      add_part_dparam(Part::G, l[i] * l[k], l[k], out, i);
    }
    if (with_h) add_part_dparam(Part::H, jac, l[j] * l[k], out, i);
  }
}

}  // namespace palpa::material
