// SPDX-License-Identifier: Apache-2.0
#pragma once
// The --probe-at option of the commands that move a scene's tool start (organ-poke, mesh): three
// coordinates in metres, checked before any work.

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace tissuesim::app {

/// None for no values; the point for three finite ones within 10 m of the origin. @throws
/// CommandError otherwise.
std::optional<Eigen::Vector3d> probeAtOption(const std::vector<double>& values_m);

}  // namespace tissuesim::app
