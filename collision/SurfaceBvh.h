// SPDX-License-Identifier: Apache-2.0
#pragma once
// A bounding-volume hierarchy (FCL, AABB) over a triangle surface that deforms: built once,
// then refitted to new vertex positions each physics step rather than rebuilt. Finds the
// triangles a capsule (the instrument's shaft and blunt tip) touches, every step; and the
// distance from it to the surface, on demand (an OBBRSS tree built for the query: FCL's mesh
// distance needs one).

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tissuesim {

/// The closest approach of a capsule and the surface (m). Negative distance is not reported:
/// FCL returns 0 on contact and `isColliding` says so.
struct CapsuleSurfaceDistance {
  double distance_m = 0.0;
  bool isColliding = false;
  Eigen::Vector3d pointOnCapsule_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d pointOnSurface_m = Eigen::Vector3d::Zero();
  int triangle = -1;  ///< index of the closest triangle
};

/// A capsule along its local z axis, centred at the pose's origin.
struct Capsule {
  double radius_m = 0.0;
  double length_m = 0.0;  ///< of the cylinder part, between the two hemisphere centres
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

class SurfaceBvh {
 public:
  /// @param vertices #V by 3 positions (m); @param triangles #F by 3 vertex indices.
  /// @throws std::invalid_argument for an empty surface or out-of-range indices.
  SurfaceBvh(const Eigen::Ref<const Eigen::MatrixX3d>& vertices,
             const Eigen::Ref<const Eigen::MatrixX3i>& triangles);
  ~SurfaceBvh();
  SurfaceBvh(const SurfaceBvh&) = delete;
  SurfaceBvh& operator=(const SurfaceBvh&) = delete;

  /// Moves the vertices (same count and order) and refits the hierarchy's bounding volumes.
  void refit(const Eigen::Ref<const Eigen::MatrixX3d>& vertices);

  CapsuleSurfaceDistance distanceTo(const Capsule& capsule) const;

  /// The triangles the capsule intersects (FCL's traversal, an exact axis-to-triangle distance
  /// test at the leaves), into `triangles`; allocates nothing once `triangles` has grown.
  void touchedTriangles(const Capsule& capsule, std::vector<int>& triangles) const;

  int vertexCount() const;
  int triangleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace tissuesim
