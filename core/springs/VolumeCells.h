// SPDX-License-Identifier: Apache-2.0
#pragma once
// The cells whose volume the volume term holds (VolumeForceField.h): the tets grouped so that
// each group fills one lattice cube. A lattice mesh (LatticeMesher, BlockMesher) cuts every cube
// into six Kuhn tets that share its main diagonal, so each of them has a node at its bounding
// box's lowest corner and one at its highest, the cube's diagonal: tets with the same such pair
// of nodes belong to one cube. Any other tet (one without both corners, as in a mesh from
// TetGen or Gmsh) is a cell of its own, and the term falls back to one constraint per tet.
//
// Why cells and not tets: a volume constraint per linear tet locks. A lattice has about six
// tets but one node (three DOFs) per cube, so six constraints per node leave a nearly
// incompressible network far stiffer than the continuum; one constraint per cube (the mean
// dilatation of the Q1/P0 hexahedron) leaves three DOFs per constraint. It also costs a sixth
// as many rank-one terms.
//
// Shapes: a cell has at most kMaxNodes nodes, in slots 0 .. nodeCount - 1 of its column.

#include <vector>

#include <Eigen/Core>

namespace tissuesim {

struct VolumeCells {
  static constexpr int kMaxNodes = 8;

  Eigen::Matrix<int, kMaxNodes, Eigen::Dynamic> nodes;  ///< kMaxNodes by #C, unused slots -1
  std::vector<int> nodeCount;                           ///< #C
  std::vector<int> tetStart;                            ///< #C + 1, into tets
  std::vector<int> tets;                                ///< #T, the tets cell by cell
  Eigen::Matrix4Xi tetSlots;      ///< 4 by #T (tet order): each tet node's slot in its cell
  Eigen::VectorXd restVolume_m3;  ///< #C, the sum of its tets' rest volumes
  /// A cube's corners around its diagonal, as slots (kMaxNodes by #C; row 0 -1 for a cell that is
  /// not a whole cube): row 0 the lowest corner, row 7 the highest, rows 1-6 the six others in
  /// turn around the diagonal, so that the cell's k-th tet (tets[tetStart + k], k = 0 .. 5) is
  /// (row 0, row k + 1, row (k + 1) % 6 + 1, row 7) with the mesh's orientation: its signed
  /// volume is d . (h_k x h_k+1) / 6, d and h_k the highest and the k-th corner less the lowest.
  Eigen::Matrix<int, kMaxNodes, Eigen::Dynamic> cubeSlots;

  bool isCube(Eigen::Index c) const { return cubeSlots(0, c) >= 0; }

  Eigen::Index cellCount() const { return nodes.cols(); }
  /// Node pairs (a < b) that share a cell, each once (2 by #P).
  Eigen::Matrix2Xi nodePairs() const;
};

/// @param tetRestVolume_m3 #T, > 0.
VolumeCells groupTetsIntoCells(const Eigen::Matrix3Xd& restPositions_m,
                               const Eigen::Matrix4Xi& tets,
                               const Eigen::VectorXd& tetRestVolume_m3);

}  // namespace tissuesim
