// SPDX-License-Identifier: Apache-2.0
#include "sim/ToolClearance.h"

#include <algorithm>
#include <cmath>

#include "forces/CapsuleGap.h"
#include "mesh/SegmentTriangleDistance.h"

namespace tissuesim {

ToolClearance::ToolClearance(const TetMesh& mesh)
    : m_faces(boundaryFaces(mesh)),
      m_nodes(faceNodes(m_faces)),
      m_gaps(static_cast<std::size_t>(mesh.nodeCount()), 0.0) {}

double ToolClearance::operator()(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, double radius_m,
                                 double exactWithin_m) const {
  for (const int node : m_nodes)
    m_gaps[static_cast<std::size_t>(node)] = capsuleGap(x.col(node), a, b, radius_m).gap_m;
  const double farthestFromACorner = 1.0 / std::sqrt(3.0);
  double clearance_m = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < m_faces.cols(); ++f) {
    const Eigen::Vector3d p = x.col(m_faces(0, f)), q = x.col(m_faces(1, f)),
                          r = x.col(m_faces(2, f));
    const double longest =
        std::sqrt(std::max({(q - p).squaredNorm(), (r - q).squaredNorm(), (p - r).squaredNorm()}));
    const double nearestCorner = std::min({m_gaps[static_cast<std::size_t>(m_faces(0, f))],
                                           m_gaps[static_cast<std::size_t>(m_faces(1, f))],
                                           m_gaps[static_cast<std::size_t>(m_faces(2, f))]});
    double face_m = nearestCorner - farthestFromACorner * longest;
    if (face_m >= clearance_m) continue;  // this face cannot be the nearest
    if (face_m < exactWithin_m) face_m = closestSegmentTriangle(a, b, p, q, r).distance - radius_m;
    clearance_m = std::min(clearance_m, face_m);
  }
  return clearance_m;
}

}  // namespace tissuesim
