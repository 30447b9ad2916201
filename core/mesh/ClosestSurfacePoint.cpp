// SPDX-License-Identifier: Apache-2.0
#include "mesh/ClosestSurfacePoint.h"

#include <algorithm>
#include <limits>

#include "mesh/SegmentTriangleDistance.h"

namespace tissuesim {

ClosestSurfacePoint::ClosestSurfacePoint(const TriangleSurface& surface) : m_surface(surface) {
  const Eigen::Index count = surface.triangleCount();
  m_centres_m.resize(3, count);
  m_radii_m.resize(count);
  for (Eigen::Index t = 0; t < count; ++t) {
    const Eigen::Vector3d centre = (surface.vertices_m.col(surface.triangles(0, t)) +
                                    surface.vertices_m.col(surface.triangles(1, t)) +
                                    surface.vertices_m.col(surface.triangles(2, t))) /
                                   3.0;
    m_centres_m.col(t) = centre;
    double radius = 0.0;
    for (int c = 0; c < 3; ++c)
      radius = std::max(radius, (surface.vertices_m.col(surface.triangles(c, t)) - centre).norm());
    m_radii_m(t) = radius;
  }
}

Eigen::Vector3d ClosestSurfacePoint::operator()(const Eigen::Vector3d& point_m) const {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d closest = point_m;
  for (Eigen::Index t = 0; t < m_centres_m.cols(); ++t) {
    // A triangle lies within its radius of its centre: one farther off than the best so far by
    // more than that cannot hold a nearer point.
    if ((m_centres_m.col(t) - point_m).norm() - m_radii_m(t) >= best) continue;
    Eigen::Vector3d weights;
    const Eigen::Vector3d candidate =
        closestPointOnTriangle(point_m, m_surface.vertices_m.col(m_surface.triangles(0, t)),
                               m_surface.vertices_m.col(m_surface.triangles(1, t)),
                               m_surface.vertices_m.col(m_surface.triangles(2, t)), weights);
    const double distance = (candidate - point_m).norm();
    if (distance < best) {
      best = distance;
      closest = candidate;
    }
  }
  return closest;
}

}  // namespace tissuesim
