// SPDX-License-Identifier: Apache-2.0
#pragma once
// A triangle surface: vertices 3 by #V (m) and triangles 3 by #F (vertex indices), the visual
// surface of an organ or the boundary a tet mesh is built inside.

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tissuesim {

struct TriangleSurface {
  Eigen::Matrix3Xd vertices_m;
  Eigen::Matrix3Xi triangles;

  Eigen::Index vertexCount() const { return vertices_m.cols(); }
  Eigen::Index triangleCount() const { return triangles.cols(); }
};

/// A mesh or surface file that cannot be used; the message names the file and the problem.
class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The volume a closed, outward-oriented surface encloses (m^3), by the divergence theorem;
/// negative for inward orientation, meaningless for an open surface.
double enclosedVolume(const TriangleSurface& surface);

/// The generalised winding number of the surface around point p (Jacobson et al. 2013): 1
/// inside a closed outward surface, 0 outside, and a graceful fraction near holes.
double windingNumber(const TriangleSurface& surface, const Eigen::Vector3d& p);

/// Each vertex's share of the surface's area: a third of every triangle it is a corner of (m^2;
/// #V). Vertices (3 by #V) and triangles (3 by #F) apart, for a tet mesh's boundary faces too.
Eigen::VectorXd vertexAreas(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& triangles);

/// Where the ray from `from` along unit `direction` first crosses the triangles (3 by #F into
/// `vertices`, 3 by #V, m), into crossing_m; false when it misses them all.
bool firstCrossing(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& triangles,
                   const Eigen::Vector3d& from, const Eigen::Vector3d& direction,
                   Eigen::Vector3d& crossing_m);

/// Area-weighted vertex normals (3 by #V, unit; outward for an outward surface; zero for a
/// vertex no triangle uses).
Eigen::Matrix3Xd vertexNormals(const TriangleSurface& surface);

}  // namespace tissuesim
