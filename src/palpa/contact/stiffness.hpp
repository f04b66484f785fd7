// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Choosing and correcting the penalty stiffness k so that the deepest
// penetration lands near a target (the thesis aims at about 0.3 mm, §7.3.4).
// One rule for every driver: an initial k from the load or from the modulus,
// then, after each equilibrium, a correction by the depth-to-target ratio.
//
// A penetrating point at depth δ carries 2kδ. Under a fixed load the deepest
// penetration goes as k^−α: α = 1 where the contact area stays put (a flat
// punch), α = ½ where it grows with the approach (a smooth body on a plane:
// the load is k times the penetrated volume, ∝ kδ² as the contact radius² ∝
// δ, Hertz's geometry). k·(δ/target)^(1/α) is then the k that lands on the
// target, clamped so that one bad solve cannot throw k off by more than a
// factor `max_factor`. Units: k [N/m], depths [m], loads [N], areas [m²],
// moduli [Pa].

#include <optional>
#include <utility>

namespace palpa::contact {

// If a load is carried evenly by `contact_points` points, each at the target
// depth: k = load / (2 · contact_points · target). The deepest point carries
// more than an even share, so expect the maximum penetration above target by
// the peak-to-mean pressure ratio (the controller corrects it). Throws
// palpa::Error (Input) unless all three are > 0.
double stiffness_for_penetration(double load, double contact_points, double target);
// k such that a point of area `area` under a pressure `pressure` sits at the
// target depth: pressure·area / (2·target).
double stiffness_for_pressure(double pressure, double area, double target);
// k·(max_depth/target)^(1/exponent) with the factor clamped to
// [1/max_factor, max_factor]; k unchanged when nothing penetrated
// (max_depth ≤ 0). exponent: α above, > 0.
double corrected_stiffness(double k, double max_depth, double target, double max_factor = 10.0,
                           double exponent = 1.0);
// α of depth ∝ k^−α measured by two solves under the same load, (k0, d0) and
// (k1, d1), clamped to [¼, 1] (between the two geometries above, with room
// for a contact that grows faster); `fallback` when the two cannot tell it
// (a depth ≤ 0, or k0 and k1 within 1% of each other).
double penetration_exponent(double k0, double d0, double k1, double d1, double fallback);

struct StiffnessPolicy {
  double target = 3e-4;  // the deepest penetration aimed at [m], > 0
  // The depth-to-target ratios accepted: a solve whose deepest penetration
  // lies within [low, high]·target keeps k.
  double low = 0.85;
  double high = 1.15;
  double max_factor = 10.0;  // clamp of one correction (≥ 1)
  // Applied on top of each correction (> 1 aims below the target, so that a
  // driver that accepts any depth below it stops sooner).
  double overshoot = 1.0;
  // α assumed by a correction (1: the contact area stays put, ½: it grows as
  // a smooth body's does).
  double exponent = 1.0;
  // Whether a correction after the first one of a sequence takes α from the
  // last two solves instead (penetration_exponent, `exponent` the fallback).
  bool measure_exponent = false;
};

// The outer loop's decision after an equilibrium.
class StiffnessController {
 public:
  explicit StiffnessController(const StiffnessPolicy& policy);
  const StiffnessPolicy& policy() const noexcept { return policy_; }
  // The ratio max_depth/target of the last solve.
  double ratio(double max_depth) const noexcept { return max_depth / policy_.target; }
  bool accepts(double max_depth) const noexcept;
  // The next k: k itself when accepts(max_depth), else the clamped
  // correction times the overshoot. Remembers (k, max_depth) for the next
  // correction of the sequence (measure_exponent).
  double next(double k, double max_depth);
  // Starts a new sequence: the solves before no longer inform α (a new load,
  // geometry or support).
  void restart() noexcept { last_.reset(); }

 private:
  StiffnessPolicy policy_;
  std::optional<std::pair<double, double>> last_;  // (k, max_depth) of the last correction
};

}  // namespace palpa::contact
