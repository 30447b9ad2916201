// SPDX-License-Identifier: Apache-2.0
#include "sim/ToolProxy.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace tissuesim {

ToolProxy::ToolProxy(const InstrumentPose& start, ToolMotionLimits limits)
    : m_limits(limits), m_pose(start) {
  m_pose.direction.normalize();
}

double ToolProxy::speedLimit_m_s(double clearance_m) const {
  const double nearSpeed = m_limits.nearSpeed_m_s;
  if (!(nearSpeed < m_limits.maxSpeed_m_s)) return m_limits.maxSpeed_m_s;
  const double beyond_m = clearance_m - m_limits.nearClearance_m;
  if (!(beyond_m > 0.0)) return nearSpeed;  // near, in contact, or not known (NaN)
  // Braking at half the acceleration limit leaves the other half to follow the curve itself.
  const double braking = 0.5 * m_limits.maxAcceleration_m_s2;
  return std::min(m_limits.maxSpeed_m_s,
                  std::sqrt(nearSpeed * nearSpeed + 2.0 * braking * beyond_m));
}

const InstrumentPose& ToolProxy::advance(const InstrumentPose& target, double h_s,
                                         double clearance_m) {
  m_pose.isGrasping = target.isGrasping;
  if (!(h_s > 0.0) || !target.tip_m.allFinite() || !target.direction.allFinite()) return m_pose;
  const double aMax = m_limits.maxAcceleration_m_s2;
  const Eigen::Vector3d error = target.tip_m - m_pose.tip_m;
  const double distance = error.norm();
  if (distance <= aMax * h_s * h_s && m_velocity_m_s.norm() <= aMax * h_s) {
    m_pose.tip_m = target.tip_m;  // within one step's braking: settle
    m_velocity_m_s.setZero();
  } else {
    // The fastest speed from which braking at aMax, a step at a time, stops on the target:
    // v^2 / (2 a) + v h / 2 = |e|, and never more than one step's way to it.
    const double stoppable =
        aMax * (std::sqrt(0.25 * h_s * h_s + 2.0 * distance / aMax) - 0.5 * h_s);
    const double wantedSpeed = std::min({speedLimit_m_s(clearance_m), stoppable, distance / h_s});
    const Eigen::Vector3d wanted =
        distance > 0.0 ? (wantedSpeed / distance) * error : Eigen::Vector3d::Zero().eval();
    Eigen::Vector3d change = wanted - m_velocity_m_s;
    const double largestChange = aMax * h_s;
    if (change.norm() > largestChange) change *= largestChange / change.norm();
    m_velocity_m_s += change;
    m_pose.tip_m += h_s * m_velocity_m_s;
  }
  // The shaft turns at a bounded rate about the axis between its direction and the target's.
  const Eigen::Vector3d to = target.direction.normalized();
  const double angle = std::acos(std::clamp(m_pose.direction.dot(to), -1.0, 1.0));
  const double largestTurn = m_limits.maxTurnRate_rad_s * h_s;
  if (angle <= largestTurn) {
    m_pose.direction = to;
  } else {
    Eigen::Vector3d axis = m_pose.direction.cross(to);
    if (axis.norm() < 1e-12) axis = m_pose.direction.unitOrthogonal();  // opposite: any axis
    m_pose.direction =
        (Eigen::AngleAxisd(largestTurn, axis.normalized()) * m_pose.direction).normalized();
  }
  return m_pose;
}

}  // namespace tissuesim
