// SPDX-License-Identifier: Apache-2.0
#pragma once
// A box meshed with tets: a regular grid of cells, each split into six tets around its main
// diagonal (Kuhn's subdivision), which needs no alternation for conforming faces. Used for the
// virtual tensile specimen (the paper's samples were 55 x 20 x 5 mm) and for test blocks.

#include <vector>

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

/// @param size_m    edge lengths along x, y, z (m), each > 0
/// @param cells     cells along x, y, z, each >= 1
/// @param origin_m  the box's minimum corner (m)
/// Node (i, j, k) has index i + (nx + 1) (j + (ny + 1) k). All tets are positively oriented.
TetMesh makeBlockMesh(const Eigen::Vector3d& size_m, const Eigen::Vector3i& cells,
                      const Eigen::Vector3d& origin_m = Eigen::Vector3d::Zero());

/// The same on a rectilinear grid: nodes at every (xs[i], ys[j], zs[k]) (m; each list strictly
/// increasing, at least two entries), cells of any spacing (a grid graded towards a tool).
TetMesh makeRectilinearMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                            const std::vector<double>& zs);

}  // namespace tissuesim
