// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Choosing and correcting the penalty stiffness k so that the deepest
// penetration lands near a target (the thesis aims at about 0.3 mm, §7.3.4).
// One rule for every driver: an initial k from the load or from the modulus,
// then, after each equilibrium, a correction by the depth-to-target ratio.
//
// A penetrating point at depth δ carries 2kδ; under a fixed load and contact
// area the depth scales as 1/k, so k·δ/target is the k that lands on the
// target, clamped so that one bad solve cannot throw k off by more than a
// factor `max_factor`. Units: k [N/m], depths [m], loads [N], areas [m²],
// moduli [Pa].

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
// k·max_depth/target with the factor clamped to [1/max_factor, max_factor];
// k unchanged when nothing penetrated (max_depth ≤ 0).
double corrected_stiffness(double k, double max_depth, double target, double max_factor = 10.0);

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
  // proportional correction times the overshoot.
  double next(double k, double max_depth) const;

 private:
  StiffnessPolicy policy_;
};

}  // namespace palpa::contact
