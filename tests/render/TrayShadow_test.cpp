// SPDX-License-Identifier: Apache-2.0
#include "render/TrayShadow.h"

#include <gtest/gtest.h>

#include <vtkUnsignedCharArray.h>

#include "render/MottledColour.h"

namespace tissuesim {
namespace {

/// The cell a point on the tests' tray (x, z) falls in.
std::pair<int, int> cellOf(const Eigen::Vector2d& xz) {
  const Eigen::Vector2d cell = (xz - Eigen::Vector2d(-0.2, -0.2)) / (0.4 / TrayShadow::kCells);
  return {static_cast<int>(cell.x()), static_cast<int>(cell.y())};
}

TEST(TrayShadow, APointShadowsWhereTheLampProjectsItAndNowhereFar) {
  TrayShadow shadow(0.0, {-0.2, -0.2}, 0.4);  // 0.4 m at y = 0
  const Eigen::Vector3d point(0.0, 0.1, 0.0);
  // Along the lamp's direction: lower, so further from the point in x and z the higher it is.
  const Eigen::Vector2d onTray = shadow.project(point);
  EXPECT_NE(onTray, Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(shadow.project(Eigen::Vector3d(onTray.x(), 0.0, onTray.y())), onTray);
  Eigen::Matrix3Xd points(3, 1);
  points.col(0) = point;
  shadow.update(points, Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY(), 0.0, 0.0);
  const auto [i, j] = cellOf(onTray);
  EXPECT_GT(shadow.shade(i, j), 0.1);
  EXPECT_LT(shadow.shade(i, j), 1.0);  // one point's splat, blurred: soft
  // The running sums of the blur leave rounding, far below a texel's 1/255.
  EXPECT_LT(shadow.shade((i + TrayShadow::kCells / 2) % TrayShadow::kCells, j), 1e-6);
  // Nothing: no shadow anywhere.
  shadow.update(Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY(), 0.0,
                0.0);
  EXPECT_LT(shadow.shade(i, j), 1e-6);
}

TEST(TrayShadow, AFilledRegionIsFullyShadowedInsideAndSoftAtItsEdge) {
  TrayShadow shadow(0.0, {-0.2, -0.2}, 0.4);  // 0.4 m at y = 0
  // A 6 cm square of points 1 mm apart at 5 cm height.
  Eigen::Matrix3Xd points(3, 61 * 61);
  for (int a = 0; a < 61; ++a) {
    for (int b = 0; b < 61; ++b) points.col(a * 61 + b) << -0.03 + a * 1e-3, 0.05, -0.03 + b * 1e-3;
  }
  shadow.update(points, Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY(), 0.0, 0.0);
  const auto [i, j] = cellOf(shadow.project(Eigen::Vector3d(0.0, 0.05, 0.0)));
  EXPECT_GT(shadow.shade(i, j), 0.999);
  // Walking out along x: from full to none through values in between.
  bool sawPartial = false;
  int k = i;
  for (; k < TrayShadow::kCells && shadow.shade(k, j) > 1e-6; ++k)
    sawPartial = sawPartial || (shadow.shade(k, j) > 0.05 && shadow.shade(k, j) < 0.95);
  EXPECT_TRUE(sawPartial);
  EXPECT_LT(k, TrayShadow::kCells);
}

TEST(TrayShadow, TheToolsShaftCastsAShadowBelowTheTray) {
  TrayShadow shadow(0.0, {-0.2, -0.2}, 0.4);  // 0.4 m at y = 0
  // A vertical shaft, its tip 5 cm above the tray: its shadow runs from the tip's along the lamp.
  const Eigen::Vector3d tip(0.05, 0.05, 0.05);
  shadow.update(Eigen::Matrix3Xd(3, 0), tip, -Eigen::Vector3d::UnitY(), 0.0025, 0.1);
  const auto [i, j] = cellOf(shadow.project(tip));
  EXPECT_GT(shadow.shade(i, j), 0.05);
  const auto [i2, j2] = cellOf(shadow.project(tip + Eigen::Vector3d(0.0, 0.08, 0.0)));
  EXPECT_GT(shadow.shade(i2, j2), 0.05);
  // A point under the tray casts nothing.
  Eigen::Matrix3Xd below(3, 1);
  below.col(0) = Eigen::Vector3d(0.0, -0.01, 0.0);
  shadow.update(below, tip, -Eigen::Vector3d::UnitY(), 0.0, 0.0);
  const auto [i3, j3] = cellOf(Eigen::Vector2d(0.0, 0.0));
  EXPECT_LT(shadow.shade(i3, j3), 1e-6);
}

TEST(MottledColour, VariesSmoothlyAndStaysNearTheBase) {
  const Eigen::Vector3d base(0.30, 0.035, 0.025);
  Eigen::Matrix3Xd points(3, 200);
  for (int k = 0; k < 200; ++k) points.col(k) << 1e-3 * k, 0.02, -0.01;
  const vtkSmartPointer<vtkUnsignedCharArray> colours = mottledColour(points, base);
  ASSERT_EQ(colours->GetNumberOfTuples(), 200);
  double lowest = 1.0, highest = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double red = colours->GetComponent(k, 0) / 255.0;
    lowest = std::min(lowest, red);
    highest = std::max(highest, red);
    if (k > 0) {
      EXPECT_LE(std::abs(colours->GetComponent(k, 0) - colours->GetComponent(k - 1, 0)), 3.0);
    }
  }
  EXPECT_GT(highest - lowest, 0.02);  // it varies
  EXPECT_GT(lowest, 0.8 * base.x() - 0.01);
  EXPECT_LT(highest, 1.15 * base.x() + 0.01);
  // The same everywhere, every time.
  const vtkSmartPointer<vtkUnsignedCharArray> again = mottledColour(points, base);
  for (int k = 0; k < 200; ++k) EXPECT_EQ(colours->GetComponent(k, 0), again->GetComponent(k, 0));
  for (int k = 0; k < 200; ++k) {
    const double n = smoothNoise(points.col(k), 0.01);
    EXPECT_GE(n, -1.0);
    EXPECT_LE(n, 1.0);
  }
}

}  // namespace
}  // namespace tissuesim
