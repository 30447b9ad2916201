// SPDX-License-Identifier: Apache-2.0
#pragma once
// A point's gap to a capsule (the segment from tip centre a to b, radius R), and the capsule's
// outward normal there:
//
//   c = a + t (b - a),  t = clamp((s - a).(b - a) / |b - a|^2, 0, 1)   (the closest point)
//   g = |s - c| - R (m),  n = (s - c) / |s - c|   (on the axis itself: straight out of the tip)

#include <algorithm>

#include <Eigen/Core>

namespace tissuesim {

struct CapsuleGap {
  double gap_m;
  Eigen::Vector3d normal;
};

inline CapsuleGap capsuleGap(const Eigen::Vector3d& s, const Eigen::Vector3d& tip_m,
                             const Eigen::Vector3d& top_m, double radius_m) {
  const Eigen::Vector3d axis = top_m - tip_m;
  const double t = std::clamp((s - tip_m).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
  const Eigen::Vector3d away = s - (tip_m + t * axis);
  const double distance = away.norm();
  const Eigen::Vector3d normal =
      distance > 0.0 ? Eigen::Vector3d(away / distance) : Eigen::Vector3d(-axis.normalized());
  return {distance - radius_m, normal};
}

}  // namespace tissuesim
