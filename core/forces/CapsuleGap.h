// SPDX-License-Identifier: Apache-2.0
#pragma once
// A point's gap to a capsule (the segment from tip centre a to b, radius R), and the capsule's
// outward normal there:
//
//   c = a + t (b - a),  t = clamp((s - a).(b - a) / |b - a|^2, 0, 1)   (the closest point)
//   g = |s - c| - R (m),  n = (s - c) / |s - c|   (on the axis itself: straight out of the tip)
//
// and g's second derivative in s, the normal's turning: (P - n n^T) / |s - c|, P the identity
// where c is an end of the segment (a round end: n turns every way) and I - e e^T beside the
// shaft (e the axis's direction: n does not turn along it).

#include <algorithm>

#include <Eigen/Core>

namespace tissuesim {

struct CapsuleGap {
  double gap_m;
  Eigen::Vector3d normal;
  double distance_m;   ///< |s - c|
  bool isBesideShaft;  ///< 0 < t < 1: c inside the segment
};

/// g's Hessian in s (1/m) at `at`, for the capsule from tip_m to top_m; zero on the axis.
inline Eigen::Matrix3d capsuleGapCurvature(const CapsuleGap& at, const Eigen::Vector3d& tip_m,
                                           const Eigen::Vector3d& top_m) {
  if (!(at.distance_m > 0.0)) return Eigen::Matrix3d::Zero();
  Eigen::Matrix3d turning = Eigen::Matrix3d::Identity() - at.normal * at.normal.transpose();
  if (at.isBesideShaft) {
    const Eigen::Vector3d axis = (top_m - tip_m).normalized();
    turning -= axis * axis.transpose();
  }
  return turning / at.distance_m;
}

inline CapsuleGap capsuleGap(const Eigen::Vector3d& s, const Eigen::Vector3d& tip_m,
                             const Eigen::Vector3d& top_m, double radius_m) {
  const Eigen::Vector3d axis = top_m - tip_m;
  const double t = std::clamp((s - tip_m).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
  const Eigen::Vector3d away = s - (tip_m + t * axis);
  const double distance = away.norm();
  const Eigen::Vector3d normal =
      distance > 0.0 ? Eigen::Vector3d(away / distance) : Eigen::Vector3d(-axis.normalized());
  return {distance - radius_m, normal, distance, t > 0.0 && t < 1.0};
}

}  // namespace tissuesim
