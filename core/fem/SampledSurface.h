// SPDX-License-Identifier: Apache-2.0
#pragma once
// The probe's penalty points on a quadratic body's surface: the linear mesh's boundary faces, each
// cut into four triangles through its edges' midpoints (the quadratic surface's pieces), and each
// piece cut into small triangles about `spacing_m` apart, a point at each one's centroid between
// the piece's three nodes with its share of the area:
//
//   k_p = pressureStiffness (Pa/m) x the small triangle's area (m^2)   (N/m)
//
// so the penalty per unit area does not depend on the sampling (CapsulePenalty.h), and the probe
// meets the surface between the nodes as well as at them.

#include <vector>

#include <Eigen/Core>

#include "fem/QuadraticTetMesh.h"
#include "forces/CapsulePenalty.h"
#include "mesh/TetMesh.h"

namespace tissuesim {

/// The quadratic surface's pieces (3 by 4 #faces, node ids of `quadratic`, made from `linear`).
Eigen::Matrix3Xi quadraticSurfacePieces(const TetMesh& linear, const QuadraticTetMesh& quadratic);

/// The points on the pieces whose centroid lies within reach_m of centre_m (every piece where
/// reach_m is infinite). spacing_m > 0.
std::vector<CapsulePenalty::Point> sampleSurfacePoints(
    const QuadraticTetMesh& quadratic, const Eigen::Matrix3Xi& pieces, double spacing_m,
    double pressureStiffness_Pa_m, const Eigen::Vector3d& centre_m, double reach_m);

}  // namespace tissuesim
