// SPDX-License-Identifier: Apache-2.0
#pragma once
// A per-node summary of the springs' stretch, for colour maps and exports: at each node, the
// stretch lambda = |x_b - x_a| / L0 of the incident spring farthest from 1 (stretched or
// compressed), 1 where no spring meets the node. Shapes: x 3 by #V (m), stretch #V.

#include <Eigen/Core>

#include "springs/SpringMesh.h"

namespace tissuesim {

/// stretch (resized to #V if needed) overwritten with each node's extreme stretch at x.
void nodeStretch(const SpringMesh& mesh, const Eigen::Matrix3Xd& x, Eigen::VectorXd& stretch);

}  // namespace tissuesim
