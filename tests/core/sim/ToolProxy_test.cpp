// SPDX-License-Identifier: Apache-2.0
#include "sim/ToolProxy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/RealTimeLoop.h"

namespace tissuesim {
namespace {

constexpr double kStep_s = 1e-3;

TEST(ToolProxy, ACursorJumpIsFollowedAtBoundedSpeedAndAcceleration) {
  const ToolMotionLimits limits;
  ToolProxy proxy({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, limits);
  const InstrumentPose target{Eigen::Vector3d(0.1, 0.0, 0.0), -Eigen::Vector3d::UnitY()};
  Eigen::Vector3d previousVelocity = Eigen::Vector3d::Zero();
  double fastest = 0.0, furthest = 0.0;
  int arrived = -1;
  for (int n = 0; n < 1000; ++n) {
    const InstrumentPose& pose = proxy.advance(target, kStep_s);
    const Eigen::Vector3d& v = proxy.velocity_m_s();
    EXPECT_LE(v.norm(), limits.maxSpeed_m_s * (1.0 + 1e-12)) << n;
    EXPECT_LE((v - previousVelocity).norm(), limits.maxAcceleration_m_s2 * kStep_s * (1.0 + 1e-12))
        << n;
    previousVelocity = v;
    fastest = std::max(fastest, v.norm());
    furthest = std::max(furthest, pose.tip_m.x());
    if (arrived < 0 && pose.tip_m == target.tip_m) arrived = n;
  }
  // 10 cm: 50 ms up to 0.5 m/s, 150 ms at it, 50 ms braking; then it rests on the target.
  EXPECT_NEAR(fastest, limits.maxSpeed_m_s, 1e-9);
  ASSERT_GE(arrived, 0);
  EXPECT_LT(arrived, 300);
  EXPECT_GT(arrived, 240);
  EXPECT_LE(furthest, 0.1 + 1e-9);  // no overshoot
  EXPECT_EQ(proxy.pose().tip_m, target.tip_m);
  EXPECT_EQ(proxy.velocity_m_s().norm(), 0.0);
}

TEST(ToolProxy, SlowMotionIsFollowedClosely) {
  // A hand moving the cursor at 5 cm/s: the tool lags by v^2 / (2 a_max) = 0.125 mm.
  ToolProxy proxy({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, ToolMotionLimits{});
  double lag = 0.0;
  for (int n = 1; n <= 500; ++n) {
    const InstrumentPose target{Eigen::Vector3d(0.05 * n * kStep_s, 0.0, 0.0),
                                -Eigen::Vector3d::UnitY()};
    const InstrumentPose& pose = proxy.advance(target, kStep_s);
    if (n > 100) lag = std::max(lag, (target.tip_m - pose.tip_m).norm());
  }
  EXPECT_LT(lag, 2e-4);
  EXPECT_GT(lag, 5e-5);
}

TEST(ToolProxy, TheShaftTurnsAtABoundedRate) {
  const ToolMotionLimits limits;
  ToolProxy proxy({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, limits);
  const InstrumentPose target{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()};  // 90 degrees
  Eigen::Vector3d previous = proxy.pose().direction;
  int turned = -1;
  for (int n = 0; n < 1000; ++n) {
    const Eigen::Vector3d now = proxy.advance(target, kStep_s).direction;
    EXPECT_NEAR(now.norm(), 1.0, 1e-12);
    EXPECT_LE(std::acos(std::min(1.0, previous.dot(now))),
              limits.maxTurnRate_rad_s * kStep_s * (1.0 + 1e-9));
    previous = now;
    if (turned < 0 && now == target.direction) turned = n;
  }
  EXPECT_NEAR(turned, std::ceil(0.5 * M_PI / (limits.maxTurnRate_rad_s * kStep_s)), 1.0);
}

TEST(ToolProxy, NearTheOrganItMovesNoFasterThanItsNearSpeedAndBrakesToItOnTheWay) {
  // An organ whose surface is the plane x = 10 cm, the target 2 cm inside it: the tool crosses
  // the free space at its own limit, is down to the near speed by 5 mm from the surface, and
  // goes on at that speed. Without a near speed the clearance changes nothing.
  ToolMotionLimits limits;
  limits.nearSpeed_m_s = 0.01;
  limits.nearClearance_m = 0.005;
  const double surface_m = 0.1;
  const InstrumentPose target{Eigen::Vector3d(0.12, 0.0, 0.0), -Eigen::Vector3d::UnitY()};
  ToolProxy proxy({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, limits);
  ToolProxy unlimited({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, ToolMotionLimits{});
  ToolProxy plain({Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()}, ToolMotionLimits{});
  Eigen::Vector3d previousVelocity = Eigen::Vector3d::Zero();
  double fastest = 0.0;
  int arrived = -1;
  for (int n = 0; n < 4000; ++n) {
    const double clearance_m = surface_m - proxy.pose().tip_m.x();
    const InstrumentPose& pose = proxy.advance(target, kStep_s, clearance_m);
    const double speed = proxy.velocity_m_s().norm();
    EXPECT_LE((proxy.velocity_m_s() - previousVelocity).norm(),
              limits.maxAcceleration_m_s2 * kStep_s * (1.0 + 1e-12))
        << n;
    previousVelocity = proxy.velocity_m_s();
    if (clearance_m <= limits.nearClearance_m) {
      EXPECT_LE(speed, limits.nearSpeed_m_s * (1.0 + 1e-12)) << n;
    }
    EXPECT_LE(speed, proxy.speedLimit_m_s(clearance_m) * (1.0 + 1e-12)) << n;
    fastest = std::max(fastest, speed);
    if (arrived < 0 && pose.tip_m == target.tip_m) arrived = n;
    // The same clearance means nothing to a proxy with no near speed.
    EXPECT_EQ(unlimited.advance(target, kStep_s, clearance_m).tip_m,
              plain.advance(target, kStep_s).tip_m);
  }
  EXPECT_NEAR(fastest, limits.maxSpeed_m_s, 1e-9);
  // 2.5 cm at the near speed take 2.5 s; the 9.5 cm before them about a quarter of a second.
  ASSERT_GE(arrived, 0);
  EXPECT_GT(arrived, 2500);
  EXPECT_LT(arrived, 2900);
  EXPECT_EQ(proxy.speedLimit_m_s(-0.01), limits.nearSpeed_m_s) << "in contact";
  EXPECT_EQ(proxy.speedLimit_m_s(std::numeric_limits<double>::quiet_NaN()), limits.nearSpeed_m_s);
  EXPECT_EQ(proxy.speedLimit_m_s(1.0), limits.maxSpeed_m_s);
}

TEST(ToolProxy, ALiveInstrumentWithLimitsTracksItsTargetByTheStepsTime) {
  const InstrumentPose start{Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY()};
  LiveInstrument direct(start);
  LiveInstrument proxied(start, ToolMotionLimits{});
  const InstrumentPose jump{Eigen::Vector3d(0.0, -0.05, 0.0), -Eigen::Vector3d::UnitY()};
  direct.setPose(jump);
  proxied.setPose(jump);
  EXPECT_EQ(direct.poseAt(0.001).tip_m, jump.tip_m);    // without limits: where it is written
  EXPECT_EQ(proxied.poseAt(0.001).tip_m, start.tip_m);  // the first call starts the clock
  const double moved = -proxied.poseAt(0.002).tip_m.y();
  EXPECT_NEAR(moved, 10.0 * 0.001 * 0.001, 1e-15);  // one step from rest at a_max
  // A reset (time back to the start) restarts the clock: no jump.
  const Eigen::Vector3d before = proxied.poseAt(0.003).tip_m;
  EXPECT_EQ(proxied.poseAt(0.001).tip_m, before);
}

}  // namespace
}  // namespace tissuesim
