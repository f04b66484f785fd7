// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// When the contact drivers (rest, sim3d) let the spring areas follow the
// contact set between equilibria (contact/spring_areas.hpp): while they move
// by more than 1% of the area in contact, at most three times for one penalty
// stiffness. A rim vertex that touches in one solve and not in the next flips
// the areas back and forth; without the cap the re-solves cycle and the
// stiffness is never corrected.

#include <memory>
#include <span>

#include "palpa/body/contact_term.hpp"

namespace palpa::body {

class AreaUpdates {
 public:
  static constexpr double kTolerance = 0.01;  // of the area in contact
  static constexpr int kMaxUpdates = 3;       // per stiffness

  // Updates every term's spring areas that moved by more than kTolerance;
  // true if one did. Does nothing once kMaxUpdates updates have been made
  // since construction or restart().
  bool update(std::span<ContactTerm* const> terms);
  bool update(std::span<const std::unique_ptr<ContactTerm>> terms);
  // After a stiffness change: the areas may move again.
  void restart() noexcept { done_ = 0; }

 private:
  int done_ = 0;
};

}  // namespace palpa::body
