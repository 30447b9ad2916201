// SPDX-License-Identifier: Apache-2.0
#pragma once
// The closest points between a segment (the instrument's axis) and a triangle (a surface face):
// exact, from the candidates of Ericson, Real-Time Collision Detection (2005), 5.1: each segment
// end against the triangle (5.1.5), each triangle edge against the segment (5.1.9), and the
// segment's crossing of the triangle's plane when it lies inside the triangle.

#include <Eigen/Core>

namespace tissuesim {

struct SegmentTriangleClosest {
  Eigen::Vector3d onSegment = Eigen::Vector3d::Zero();
  Eigen::Vector3d onTriangle = Eigen::Vector3d::Zero();
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();  ///< barycentric of onTriangle (a, b, c)
  double distance = 0.0;
};

/// The point of triangle (a, b, c) nearest p, with its barycentric weights.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       Eigen::Vector3d& weights);

SegmentTriangleClosest closestSegmentTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                              const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                              const Eigen::Vector3d& c);

}  // namespace tissuesim
