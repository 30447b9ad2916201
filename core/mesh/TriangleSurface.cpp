// SPDX-License-Identifier: Apache-2.0
#include "mesh/TriangleSurface.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace tissuesim {

double enclosedVolume(const TriangleSurface& surface) {
  double volume = 0.0;
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    const Eigen::Vector3d a = surface.vertices_m.col(surface.triangles(0, f));
    const Eigen::Vector3d b = surface.vertices_m.col(surface.triangles(1, f));
    const Eigen::Vector3d c = surface.vertices_m.col(surface.triangles(2, f));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

double windingNumber(const TriangleSurface& surface, const Eigen::Vector3d& p) {
  // Sum of signed solid angles (Van Oosterom and Strackee 1983) over 4 pi.
  double total = 0.0;
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    const Eigen::Vector3d a = surface.vertices_m.col(surface.triangles(0, f)) - p;
    const Eigen::Vector3d b = surface.vertices_m.col(surface.triangles(1, f)) - p;
    const Eigen::Vector3d c = surface.vertices_m.col(surface.triangles(2, f)) - p;
    const double la = a.norm();
    const double lb = b.norm();
    const double lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * std::numbers::pi);
}

Eigen::VectorXd vertexAreas(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& triangles) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(vertices.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Eigen::Vector3d a = vertices.col(triangles(0, t));
    const double third =
        (vertices.col(triangles(1, t)) - a).cross(vertices.col(triangles(2, t)) - a).norm() / 6.0;
    for (int k = 0; k < 3; ++k) area[triangles(k, t)] += third;
  }
  return area;
}

bool firstCrossing(const Eigen::Matrix3Xd& vertices, const Eigen::Matrix3Xi& triangles,
                   const Eigen::Vector3d& from, const Eigen::Vector3d& direction,
                   Eigen::Vector3d& crossing_m) {
  // Moeller-Trumbore, the nearest crossing ahead of `from`.
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < triangles.cols(); ++f) {
    const Eigen::Vector3d a = vertices.col(triangles(0, f));
    const Eigen::Vector3d ab = vertices.col(triangles(1, f)) - a;
    const Eigen::Vector3d ac = vertices.col(triangles(2, f)) - a;
    const Eigen::Vector3d p = direction.cross(ac);
    const double determinant = ab.dot(p);
    if (std::abs(determinant) < 1e-30) continue;  // the ray runs along the face's plane
    const Eigen::Vector3d s = from - a;
    const double u = s.dot(p) / determinant;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(ab);
    const double v = direction.dot(q) / determinant;
    if (v < 0.0 || u + v > 1.0) continue;
    const double distance = ac.dot(q) / determinant;
    if (distance >= 0.0 && distance < nearest) nearest = distance;
  }
  if (!std::isfinite(nearest)) return false;
  crossing_m = from + nearest * direction;
  return true;
}

Eigen::Matrix3Xd vertexNormals(const TriangleSurface& surface) {
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, surface.vertices_m.cols());
  for (Eigen::Index f = 0; f < surface.triangles.cols(); ++f) {
    const Eigen::Vector3d a = surface.vertices_m.col(surface.triangles(0, f));
    const Eigen::Vector3d b = surface.vertices_m.col(surface.triangles(1, f));
    const Eigen::Vector3d c = surface.vertices_m.col(surface.triangles(2, f));
    const Eigen::Vector3d areaNormal = (b - a).cross(c - a);  // twice the area, outward
    for (int k = 0; k < 3; ++k) normals.col(surface.triangles(k, f)) += areaNormal;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const double length = normals.col(v).norm();
    if (length > 0.0) normals.col(v) /= length;
  }
  return normals;
}

}  // namespace tissuesim
