// SPDX-License-Identifier: Apache-2.0
#pragma once
// The instrument as a proxy that tracks the trainee's input (the mouse, a haptic device's
// handle) with bounded speed and acceleration, as haptic rendering separates the device from
// the tool it drives: a cursor that jumps never carries the tool through tissue in one step, and
// the force it feels stays continuous. Scripts drive the tool directly (poses as written).
//
// Per physics step h (s), position p (m), velocity v (m/s), target q:
//   e = q - p;  v_want = min(v_max, v_stop, |e| / h) e / |e|,  v_stop^2 / (2 a_max) +
//               v_stop h / 2 = |e| (the fastest speed from which the tool, braking at a_max a
//               step at a time, still stops on q)
//   v += clamp(v_want - v, a_max h);  p += h v
// and it settles on q once within a_max h^2 of it at a speed below a_max h. Where a model
// follows the probe only so fast (v_near), v_max near the organ is the clearance c's (m, the
// tool's gap to the organ, <= 0 in contact):
//   v_max(c) = v_near                                              c <= c_near
//            = min(v_max, sqrt(v_near^2 + 2 (a_max / 2) (c - c_near)))   beyond
// the fastest speed from which the tool, braking at half its limit, is down to v_near by c_near:
// it crosses free space at v_max and meets the organ no faster than the model follows. The shaft's
// direction turns towards the target's by at most omega_max h a step (about the axis they
// span). The grasper's state passes straight through.

#include <limits>

#include <Eigen/Core>

#include "forces/ContactProvider.h"

namespace tissuesim {

struct ToolMotionLimits {
  double maxSpeed_m_s = 0.5;           ///< a laparoscopic tool's quick move
  double maxAcceleration_m_s2 = 10.0;  ///< about 1 g
  double maxTurnRate_rad_s = 3.0;      ///< about 170 degrees a second
  /// The speed near the organ (m/s; infinity: no other than maxSpeed_m_s), within
  /// nearClearance_m (m) of it.
  double nearSpeed_m_s = std::numeric_limits<double>::infinity();
  double nearClearance_m = 0.0;
};

class ToolProxy {
 public:
  ToolProxy(const InstrumentPose& start, ToolMotionLimits limits);

  /// The pose after h seconds of tracking `target`, the tool's clearance from the organ at the
  /// start of them clearance_m (m; infinity: far from any).
  const InstrumentPose& advance(const InstrumentPose& target, double h_s,
                                double clearance_m = std::numeric_limits<double>::infinity());
  const InstrumentPose& pose() const { return m_pose; }
  const Eigen::Vector3d& velocity_m_s() const { return m_velocity_m_s; }
  const ToolMotionLimits& limits() const { return m_limits; }
  /// A new speed limit near the organ (m/s, > 0) from the next step on: a tool moving faster
  /// there slows at its acceleration limit.
  void setNearSpeed(double nearSpeed_m_s) { m_limits.nearSpeed_m_s = nearSpeed_m_s; }
  /// The speed limit at clearance_m from the organ (m/s; above).
  double speedLimit_m_s(double clearance_m) const;

 private:
  ToolMotionLimits m_limits;
  InstrumentPose m_pose;
  Eigen::Vector3d m_velocity_m_s = Eigen::Vector3d::Zero();
};

}  // namespace tissuesim
