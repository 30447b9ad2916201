// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tool's clearance from the organ: the distance from the capsule (the segment from the tip's
// hemisphere centre a to the shaft's end b, radius R) to the tet mesh's boundary triangles at
// positions x, less R (m; <= 0 where it touches or is inside):
//
//   c = min over faces f of d_f,   d_f = dist(segment ab, triangle f) - R        where l_f < w
//                                      = l_f                                      elsewhere
//   l_f = min over f's corners v of (dist(v, segment ab) - R) - rho_f,   rho_f = (f's longest
//         edge) / sqrt(3)
//
// rho_f is the furthest a point of a triangle lies from its nearest corner (the centre of an
// equilateral one), so l_f <= d_f: c is a lower bound of the clearance everywhere and exact
// wherever the clearance is below w. The exact distance (mesh/SegmentTriangleDistance.h) is taken
// only for the few faces within w; the rest cost a point-to-segment distance a corner. The
// corners' distances are kept in a buffer sized once: no allocation per call.

#include <limits>
#include <vector>

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

class ToolClearance {
 public:
  /// The mesh's boundary triangles (its nodes' indices; the positions come with each call).
  explicit ToolClearance(const TetMesh& mesh);

  /// The clearance (above) of the capsule from tip centre a to b (m), radius R, from the boundary
  /// at positions x (3 by #V, m), exact where it is below exactWithin_m; infinity without faces.
  double operator()(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    double radius_m, double exactWithin_m) const;

  Eigen::Index faceCount() const { return m_faces.cols(); }

 private:
  Eigen::Matrix3Xi m_faces;
  std::vector<int> m_nodes;  ///< the boundary's nodes, sorted
  mutable std::vector<double>
      m_gaps;  ///< per mesh node (the boundary's set): distance to the axis less R
};

}  // namespace tissuesim
