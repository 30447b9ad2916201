// SPDX-License-Identifier: Apache-2.0
#include "mesh/SegmentTriangleDistance.h"

#include <algorithm>
#include <array>
#include <limits>

#include <Eigen/Geometry>

namespace tissuesim {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       Eigen::Vector3d& weights) {
  // Ericson 5.1.5: find p's Voronoi region of the triangle.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    weights = {1, 0, 0};
    return a;
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    weights = {0, 1, 0};
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    weights = {1 - v, v, 0};
    return a + v * ab;
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    weights = {0, 0, 1};
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    weights = {1 - w, 0, w};
    return a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    weights = {0, 1 - w, w};
    return b + w * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  weights = {1 - v - w, v, w};
  return a + v * ab + w * ac;
}

namespace {
/// Ericson 5.1.9: closest points of segments p1-q1 and p2-q2, as parameters s and t.
void closestSegmentSegment(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1,
                           const Eigen::Vector3d& p2, const Eigen::Vector3d& q2, double& s,
                           double& t) {
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double tiny = 1e-30;
  if (a <= tiny && e <= tiny) {
    s = t = 0.0;
    return;
  }
  if (a <= tiny) {
    s = 0.0;
    t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (e <= tiny) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = d1.dot(d2);
  const double denominator = a * e - b * b;
  s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}
}  // namespace

SegmentTriangleClosest closestSegmentTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                              const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                              const Eigen::Vector3d& c) {
  SegmentTriangleClosest best;
  best.distance = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Eigen::Vector3d& onSegment, const Eigen::Vector3d& onTriangle,
                            const Eigen::Vector3d& weights) {
    const double distance = (onTriangle - onSegment).norm();
    if (distance < best.distance) best = {onSegment, onTriangle, weights, distance};
  };
  // The segment crossing the triangle's plane inside it: distance 0.
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double area2 = normal.squaredNorm();
  const double h0 = (p0 - a).dot(normal), h1 = (p1 - a).dot(normal);
  if (area2 > 0.0 && h0 != h1 && ((h0 <= 0.0 && h1 >= 0.0) || (h0 >= 0.0 && h1 <= 0.0))) {
    const Eigen::Vector3d q = p0 + (h0 / (h0 - h1)) * (p1 - p0);
    const Eigen::Vector3d weights((b - q).cross(c - q).dot(normal) / area2,
                                  (c - q).cross(a - q).dot(normal) / area2,
                                  (a - q).cross(b - q).dot(normal) / area2);
    if ((weights.array() >= 0.0).all()) {
      consider(q, weights[0] * a + weights[1] * b + weights[2] * c, weights);
      return best;
    }
  }
  for (const Eigen::Vector3d* end : {&p0, &p1}) {
    Eigen::Vector3d weights;
    const Eigen::Vector3d onTriangle = closestPointOnTriangle(*end, a, b, c, weights);
    consider(*end, onTriangle, weights);
  }
  const std::array<const Eigen::Vector3d*, 3> corners{&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& from = *corners[static_cast<std::size_t>(k)];
    const Eigen::Vector3d& to = *corners[static_cast<std::size_t>((k + 1) % 3)];
    double s = 0.0, t = 0.0;
    closestSegmentSegment(p0, p1, from, to, s, t);
    Eigen::Vector3d weights = Eigen::Vector3d::Zero();
    weights[k] = 1.0 - t;
    weights[(k + 1) % 3] = t;
    consider(p0 + s * (p1 - p0), from + t * (to - from), weights);
  }
  return best;
}

}  // namespace tissuesim
