// SPDX-License-Identifier: Apache-2.0
#pragma once
// The value below which a share of a sample lies (nearest rank): the commands' step-time
// medians and 99th percentiles.

#include <algorithm>
#include <cmath>
#include <vector>

namespace tissuesim::app {

/// The smallest value with at least `share` (0 to 1) of `values` at or below it; 0 for none.
inline double percentile(std::vector<double> values, double share) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(share * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, rank > 0 ? rank - 1 : 0)];
}

}  // namespace tissuesim::app
