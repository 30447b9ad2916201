// SPDX-License-Identifier: Apache-2.0
#pragma once
// Adding a symmetric 3x3 block given by its upper triangle: what the matrix-free operators'
// diagonal passes sum in scalars (an Eigen 3x3 temporary per element made those passes several
// times slower) and write once per node.

#include <Eigen/Core>

namespace tissuesim {

/// block += [b00 b01 b02; b01 b11 b12; b02 b12 b22].
inline void addSymmetric(Eigen::Matrix3d& block, double b00, double b01, double b02, double b11,
                         double b12, double b22) {
  block(0, 0) += b00;
  block(0, 1) += b01;
  block(0, 2) += b02;
  block(1, 0) += b01;
  block(1, 1) += b11;
  block(1, 2) += b12;
  block(2, 0) += b02;
  block(2, 1) += b12;
  block(2, 2) += b22;
}

}  // namespace tissuesim
