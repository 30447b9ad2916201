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

/// Signed volume of tet t of x (m^3) and its gradient into `gradient` (12 values: the 3 by 4
/// column-major dV/dx_0 .. dV/dx_3, m^2): g_1 = (x_2 - x_0) x (x_3 - x_0) / 6 and cyclically,
/// g_0 = -(g_1 + g_2 + g_3), V = (x_1 - x_0) . g_1.
inline double signedTetVolumeGradient(const Eigen::Matrix3Xd& x, const Eigen::Matrix4Xi& tets,
                                      Eigen::Index t, double* gradient) {
  const Eigen::Vector3d origin = x.col(tets(0, t));
  const Eigen::Vector3d e1 = x.col(tets(1, t)) - origin;
  const Eigen::Vector3d e2 = x.col(tets(2, t)) - origin;
  const Eigen::Vector3d e3 = x.col(tets(3, t)) - origin;
  const Eigen::Vector3d g1 = e2.cross(e3) / 6.0;
  const Eigen::Vector3d g2 = e3.cross(e1) / 6.0;
  const Eigen::Vector3d g3 = e1.cross(e2) / 6.0;
  Eigen::Map<Eigen::Matrix<double, 3, 4>> g(gradient);
  g.col(0) = -(g1 + g2 + g3);
  g.col(1) = g1;
  g.col(2) = g2;
  g.col(3) = g3;
  return e1.dot(g1);
}

/// Each node's tets, as entries 4 t + c (c: the node's corner in tet t) in tet order, at
/// entries[start[j] .. start[j + 1]) for node j (start: #V + 1).
struct NodeTetIncidence {
  std::vector<int> start;
  std::vector<int> entries;
};
NodeTetIncidence nodeTetIncidence(const Eigen::Matrix4Xi& tets, Eigen::Index nodeCount);

/// Each node's star: the nodes of its tets, itself among them, sorted, at
/// nodes[start[j] .. start[j + 1]) (a node in no tet: itself alone).
struct NodeStars {
  std::vector<int> start;
  std::vector<int> nodes;
};
NodeStars nodeStars(const Eigen::Matrix4Xi& tets, const NodeTetIncidence& incidence);
/// The index in stars.nodes of node b in a's star (b must be in it).
int starEntry(const NodeStars& stars, int a, int b);
/// For each entry e of stars.nodes (node b in a's star), the entry of a in b's star.
std::vector<int> starMirror(const NodeStars& stars);
/// The node pairs (a < b) that share a star, each once: what an element per star couples.
Eigen::Matrix2Xi starCouplings(const NodeStars& stars);

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

/// The nodes the faces use (3 by #F node indices), each once, in increasing order.
std::vector<int> faceNodes(const Eigen::Matrix3Xi& faces);

/// The number of distinct tet edges: the springs a mesh will have.
Eigen::Index countUniqueEdges(const TetMesh& mesh);

/// Validates indices and finiteness. @throws std::invalid_argument naming the tet or node.
void validateTetMesh(const TetMesh& mesh, const std::string& name);

}  // namespace tissuesim
