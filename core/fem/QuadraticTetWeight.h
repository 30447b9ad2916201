// SPDX-License-Identifier: Apache-2.0
#pragma once
// A quadratic tet mesh's own weight as nodal loads, the consistent ones of a uniform body force:
//
//   f_a = rho g integral_e N_a dV = rho g integral N_a det(dX/dxi) dxi
//
// integrated by the degree-3 rule (QuadraticTetShape.h): on a straight-edged tet, exactly
// -V_e / 20 at each corner and V_e / 5 at each edge's middle node; on a curved one (a boundary
// edge bent onto the drawn surface, fem/CurvedBoundary.h) nearly so, the loads still summing to
// rho g V_e, since the N_a sum to 1 at every point. A corner's load is negative: consistent, not
// lumped, so that the work of gravity on the quadratic field is exact.
// Units: rho kg/m^3, g m/s^2, loads N (3 by #loads).

#include <Eigen/Core>

#include "fem/QuadraticTetMesh.h"
#include "forces/NodalLoads.h"

namespace tissuesim {

/// One load per node of `mesh` (every node, in order). @throws std::invalid_argument on a
/// density that is not positive and finite, or a non-finite g.
NodalLoads quadraticTetWeight(const QuadraticTetMesh& mesh, double density_kg_m3,
                              const Eigen::Vector3d& gravity_m_s2);

}  // namespace tissuesim
