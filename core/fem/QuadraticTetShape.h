// SPDX-License-Identifier: Apache-2.0
#pragma once
// The quadratic tet's shape functions and the quadrature rules the FEM integrates with, on the
// reference tet {xi, eta, zeta >= 0, xi + eta + zeta <= 1} (volume 1/6). In barycentric
// coordinates L0 = 1 - xi - eta - zeta, L1 = xi, L2 = eta, L3 = zeta:
//
//   corner i:        N_i  = L_i (2 L_i - 1)
//   edge (i, j):     N_ij = 4 L_i L_j          (edges in QuadraticTetMesh's order)
//
// Rules (points in (xi, eta, zeta), weights summing to 1/6):
//   degree 2, four points at (a, b, b, b) permutations, a = (5 + 3 sqrt 5) / 20,
//     b = (5 - sqrt 5) / 20, weights 1/24: the isochoric energy (positive weights);
//   degree 3, Keast's five points: the centroid with weight -2/15 and (1/2, 1/6, 1/6, 1/6)
//     permutations with 3/40: the element's volume, at rest and deformed, det(dx/dxi) being
//     cubic in xi on a quadratic tet (its edges straight or curved), so integrated exactly.
//
// The map from the reference tet, X(xi) = sum_a X_a N_a(xi), has the Jacobian
//   dX/dxi = sum_a X_a (dN_a/dxi)^T   (3 by 3)
// constant where the edges are straight, linear in xi where a middle node is off its edge's
// middle (fem/CurvedBoundary.h).

#include <array>
#include <cmath>

#include <Eigen/Core>

#include "fem/QuadraticTetMesh.h"

namespace tissuesim {

struct TetQuadraturePoint {
  Eigen::Vector3d xi;  ///< reference coordinates
  double weight;       ///< reference volume weight
};

/// The degree-2 rule (four points).
inline std::array<TetQuadraturePoint, 4> tetQuadratureDegree2() {
  const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
  const double b = (5.0 - std::sqrt(5.0)) / 20.0;
  const double w = 1.0 / 24.0;
  return {{{{b, b, b}, w}, {{a, b, b}, w}, {{b, a, b}, w}, {{b, b, a}, w}}};
}

/// Keast's degree-3 rule (five points, one negative weight).
inline std::array<TetQuadraturePoint, 5> tetQuadratureDegree3() {
  const double c = 0.25;
  const double h = 0.5;
  const double s = 1.0 / 6.0;
  return {{{{c, c, c}, -2.0 / 15.0},
           {{s, s, s}, 3.0 / 40.0},
           {{h, s, s}, 3.0 / 40.0},
           {{s, h, s}, 3.0 / 40.0},
           {{s, s, h}, 3.0 / 40.0}}};
}

/// The ten shape functions' values at the barycentric coordinates l (L0 .. L3, summing to 1).
inline Eigen::Matrix<double, 10, 1> quadraticTetShapeValues(const Eigen::Vector4d& l) {
  Eigen::Matrix<double, 10, 1> values;
  for (int i = 0; i < 4; ++i) values(i) = l(i) * (2.0 * l(i) - 1.0);
  for (int e = 0; e < 6; ++e)
    values(4 + e) = 4.0 * l(kQuadraticTetEdges[e][0]) * l(kQuadraticTetEdges[e][1]);
  return values;
}

/// dN/dxi of the ten shape functions at xi (10 by 3, row a: node a's gradient).
inline Eigen::Matrix<double, 10, 3> quadraticTetShapeGradients(const Eigen::Vector3d& xi) {
  const std::array<double, 4> l = {1.0 - xi.sum(), xi.x(), xi.y(), xi.z()};
  const std::array<Eigen::Vector3d, 4> dl = {Eigen::Vector3d(-1.0, -1.0, -1.0),
                                             Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                             Eigen::Vector3d::UnitZ()};
  Eigen::Matrix<double, 10, 3> gradients;
  for (std::size_t i = 0; i < 4; ++i)
    gradients.row(static_cast<Eigen::Index>(i)) = (4.0 * l[i] - 1.0) * dl[i].transpose();
  for (int e = 0; e < 6; ++e) {
    const auto i = static_cast<std::size_t>(kQuadraticTetEdges[e][0]);
    const auto j = static_cast<std::size_t>(kQuadraticTetEdges[e][1]);
    gradients.row(4 + e) = 4.0 * (l[j] * dl[i] + l[i] * dl[j]).transpose();
  }
  return gradients;
}

/// dX/dxi of tet t at xi (above; 3 by 3, columns d/dxi, d/deta, d/dzeta).
inline Eigen::Matrix3d quadraticTetJacobian(const QuadraticTetMesh& mesh, Eigen::Index t,
                                            const Eigen::Vector3d& xi) {
  const Eigen::Matrix<double, 10, 3> gradients = quadraticTetShapeGradients(xi);
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 10; ++a) jacobian += mesh.nodes_m.col(mesh.tets(a, t)) * gradients.row(a);
  return jacobian;
}

}  // namespace tissuesim
