// SPDX-License-Identifier: Apache-2.0
#pragma once
// The cells over which a smoothed finite element takes its strain (Liu and Nguyen-Thoi's
// smoothed FEM on linear tets): each cell c owns a share of some tets, and its deformation
// gradient is the mean of theirs over that share:
//
//   V0_c = sum over c's tets t of s V0_t,   F_c = sum_t s V0_t F_t / V0_c = sum_b x_b G_cb^T  (m^3)
//   G_cb = sum over c's tets t that hold b of (s V0_t / V0_c) g_b,t               (1/m, per node b)
//
// with g_b,t the gradient of tet t's shape function b at rest and s the share:
// - faces (FS-FEM; Nguyen-Thoi, Liu, Lam and Zhang 2009): a cell per face, s = 1/4 of each of the
//   one or two tets that share it (4 or 5 nodes);
// - nodes (NS-FEM; Liu, Nguyen-Thoi, Nguyen-Xuan and Lam 2009): a cell per node, s = 1/4 of each
//   of its tets (its star).
// Every tet's volume is shared out whole, so the cells' volumes add up to the mesh's, and under a
// homogeneous deformation every F_c is that deformation.
//
// Shapes: cell c's nodes (sorted) at nodes[start[c] .. start[c + 1]), G_cb of each in
// gradients_1_m's column of the same index; volume_m3 #cells.

#include <vector>

#include <Eigen/Core>

namespace tissuesim {

struct StrainCells {
  std::vector<int> start;
  std::vector<int> nodes;
  Eigen::Matrix3Xd gradients_1_m;
  Eigen::VectorXd volume_m3;

  Eigen::Index cellCount() const { return volume_m3.size(); }
};

/// A cell per face. @throws std::invalid_argument when a tet is not positively oriented at rest.
StrainCells faceStrainCells(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets);

/// A cell per node that lies in a tet (nodes in none have no cell). @throws as faceStrainCells.
StrainCells nodeStrainCells(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets);

}  // namespace tissuesim
