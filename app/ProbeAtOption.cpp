// SPDX-License-Identifier: Apache-2.0
#include "app/ProbeAtOption.h"

#include <algorithm>
#include <cmath>

#include "app/CommandError.h"

namespace tissuesim::app {

std::optional<Eigen::Vector3d> probeAtOption(const std::vector<double>& values_m) {
  if (values_m.empty()) return std::nullopt;
  if (values_m.size() != 3 || !std::all_of(values_m.begin(), values_m.end(), [](double value) {
        return std::isfinite(value) && std::abs(value) < 10.0;
      }))
    throw CommandError(
        "--probe-at takes three finite coordinates in metres, e.g. -0.04,0.152,0.045");
  return Eigen::Vector3d(values_m[0], values_m[1], values_m[2]);
}

}  // namespace tissuesim::app
