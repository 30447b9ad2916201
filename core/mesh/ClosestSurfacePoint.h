// SPDX-License-Identifier: Apache-2.0
#pragma once
// The point of a triangle surface nearest a given point: every triangle tried, nearest bounding
// sphere first in effect (a triangle whose sphere lies farther off than the best distance so far
// is skipped). Exact; for the few thousand queries a mesh's boundary makes at load, not for a
// step loop. Shapes: the surface's vertices 3 by #V (m), its triangles 3 by #T.

#include <Eigen/Core>

#include "mesh/TriangleSurface.h"

namespace tissuesim {

class ClosestSurfacePoint {
 public:
  /// `surface` must outlive this object.
  explicit ClosestSurfacePoint(const TriangleSurface& surface);

  /// The surface's point nearest point_m (point_m itself on a surface with no triangle).
  Eigen::Vector3d operator()(const Eigen::Vector3d& point_m) const;

 private:
  const TriangleSurface& m_surface;
  Eigen::Matrix3Xd m_centres_m;  ///< each triangle's centroid
  Eigen::VectorXd m_radii_m;     ///< and the distance from it to its farthest corner
};

}  // namespace tissuesim
