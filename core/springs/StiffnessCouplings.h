// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which node pairs the network's stiffness K couples: the pattern of the system's matrix.

#include <Eigen/Core>

#include "springs/SpringMesh.h"
#include "springs/VolumeCells.h"

namespace tissuesim {

/// The node pairs K couples (2 by #P): the springs (first, in their order) and, with the volume
/// term's `cells` (null: none), the other pairs that share a cell.
Eigen::Matrix2Xi stiffnessCouplings(const SpringMesh& mesh, const VolumeCells* cells);

/// The springs (first, in their order) and the pairs of `others` (2 by #P, either order) that are
/// not springs, each once.
Eigen::Matrix2Xi stiffnessCouplings(const SpringMesh& mesh, const Eigen::Matrix2Xi& others);

}  // namespace tissuesim
