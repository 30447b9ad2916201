// SPDX-License-Identifier: Apache-2.0
#pragma once
// The detailed visual surface follows the coarser simulation mesh: each surface vertex is tied,
// once at load, to the tet containing it (or, outside the mesh, the nearest one: TetLocator) by
// barycentric weights w (4, summing to 1), and then moves as
//
//   y_v = sum_k w_vk x_{t_v k}
//
// which reproduces any affine motion of the tets exactly (rigid motions included).
// Shapes: nodes 4 by #V_surface (tet node indices), weights 4 by #V_surface.

#include <vector>

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

class SurfaceEmbedding {
 public:
  /// @param surfaceVertices_m 3 by #V_surface, in the rest frame of `mesh`.
  SurfaceEmbedding(const TetMesh& mesh, const Eigen::Matrix3Xd& surfaceVertices_m);

  /// surface (3 by #V_surface) overwritten with the embedded positions for tet-node positions x.
  void apply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& surface) const;
  /// A per-node scalar (#V of the mesh) at the surface's vertices, through the same weights:
  /// values (#V_surface) overwritten. The stretch colour map and the export use it.
  void interpolate(const Eigen::VectorXd& nodeValues, Eigen::VectorXd& values) const;
  /// Surface vertex v's position for tet-node positions x.
  Eigen::Vector3d position(Eigen::Index v, const Eigen::Matrix3Xd& x) const {
    return m_weights(0, v) * x.col(m_nodes(0, v)) + m_weights(1, v) * x.col(m_nodes(1, v)) +
           m_weights(2, v) * x.col(m_nodes(2, v)) + m_weights(3, v) * x.col(m_nodes(3, v));
  }

  /// Surface vertices that lie outside every tet (tied to the nearest by extrapolation).
  int outsideCount() const { return m_outsideCount; }
  /// The largest distance (m) from an outside vertex to its tet, at rest.
  double maxOutsideDistance_m() const { return m_maxOutsideDistance_m; }
  const Eigen::Matrix4Xi& nodes() const { return m_nodes; }
  /// The tet carrying each surface vertex (#V_surface).
  const std::vector<int>& tets() const { return m_tets; }
  const Eigen::Matrix4Xd& weights() const { return m_weights; }

 private:
  Eigen::Matrix4Xi m_nodes;
  std::vector<int> m_tets;
  Eigen::Matrix4Xd m_weights;
  int m_outsideCount = 0;
  double m_maxOutsideDistance_m = 0.0;
};

}  // namespace tissuesim
