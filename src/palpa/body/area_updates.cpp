// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/body/area_updates.hpp"

#include <vector>

namespace palpa::body {

bool AreaUpdates::update(std::span<ContactTerm* const> terms) {
  if (done_ >= kMaxUpdates) return false;
  bool changed = false;
  for (ContactTerm* t : terms) changed = t->update_areas(kTolerance) > 0.0 || changed;
  if (changed) ++done_;
  return changed;
}

bool AreaUpdates::update(std::span<const std::unique_ptr<ContactTerm>> terms) {
  std::vector<ContactTerm*> raw;
  raw.reserve(terms.size());
  for (const auto& t : terms) raw.push_back(t.get());
  return update(raw);
}

}  // namespace palpa::body
