// SPDX-License-Identifier: Apache-2.0
#pragma once
// A tetrahedral mesh: node positions and tets as four node indices each.
//
// Shapes: nodes is 3 by #V (metres, one column per node, so the columns map to a flat
// 3#V vector x0 y0 z0 x1 ... without copying); tets is 4 by #T. A tet (a, b, c, d) is
// positively oriented when (b - a) . ((c - a) x (d - a)) > 0; its volume is that over 6.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace tissuesim {

struct TetMesh {
  Eigen::Matrix3Xd nodes_m;
  Eigen::Matrix4Xi tets;

  Eigen::Index nodeCount() const { return nodes_m.cols(); }
  Eigen::Index tetCount() const { return tets.cols(); }
};

/// Signed volume of the tet (a, b, c, d) (m^3): positive when positively oriented.
inline double signedTetVolume(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// Signed volume of tet t of `positions` (3 by #V, m) with connectivity `tets` (4 by #T).
inline double signedTetVolume(const Eigen::Matrix3Xd& positions, const Eigen::Matrix4Xi& tets,
                              Eigen::Index t) {
  return signedTetVolume(positions.col(tets(0, t)), positions.col(tets(1, t)),
                         positions.col(tets(2, t)), positions.col(tets(3, t)));
}

/// What is wrong with a mesh's tets, for refusing or repairing it.
struct TetQualityReport {
  std::vector<Eigen::Index> invertedTets;  ///< signed volume < 0
  std::vector<Eigen::Index> slivers;       ///< |volume| below the sliver threshold (incl. 0)
  double minVolume_m3 = 0.0;
  double totalVolume_m3 = 0.0;
  double minDihedral_deg = 180.0;  ///< smallest dihedral angle of any tet
  double maxDihedral_deg = 0.0;
  double minRadiusRatio = 1.0;  ///< 3 r_in / R_circ: 1 for a regular tet, 0 for a flat one
};

/// A tet is a sliver when its volume is below `sliverFraction` times the volume of the
/// regular tet on its mean edge length (a volume-based radius-ratio proxy).
TetQualityReport inspectTets(const TetMesh& mesh, double sliverFraction = 1e-3);

/// The faces that belong to one tet only (3 by #F node indices), oriented outward: the
/// mesh's boundary surface, which collision and rendering use.
Eigen::Matrix3Xi boundaryFaces(const TetMesh& mesh);

/// The number of distinct tet edges: the springs a mesh will have.
Eigen::Index countUniqueEdges(const TetMesh& mesh);

/// Validates indices and finiteness. @throws std::invalid_argument naming the tet or node.
void validateTetMesh(const TetMesh& mesh, const std::string& name);

}  // namespace tissuesim
