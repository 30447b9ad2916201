// SPDX-License-Identifier: Apache-2.0
#pragma once
// Symmetric 3x3 blocks of the form
//
//   B_e = c_e n_e n_e^T + l_e I      (n_e a unit vector or zero; c_e, l_e scalars)
//
// stored as five numbers a column (5 by #E): rows 0-2 n_e, row 3 c_e, row 4 l_e. A spring's
// stiffness has this form (c = axial - lateral stiffness, l = lateral, N/m; SpringForceField):
// 40 bytes a spring instead of the 72 of the full block, which is what CG's matrix-free product
// reads per spring (SpringStiffnessProduct).

#include <Eigen/Core>

namespace tissuesim {

using AxialBlocks = Eigen::Matrix<double, 5, Eigen::Dynamic>;

/// The full 3x3 block of one column (a pointer to its five numbers).
inline Eigen::Matrix3d axialBlock(const double* column) {
  const Eigen::Map<const Eigen::Vector3d> n(column);
  Eigen::Matrix3d block = column[3] * (n * n.transpose());
  block.diagonal().array() += column[4];
  return block;
}

}  // namespace tissuesim
